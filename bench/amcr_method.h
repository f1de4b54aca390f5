// The recognizer under test behind the benchmark's Method interface: one
// amcr::Recognizer on a shared memory, reset (same seed) between sequences.
#pragma once

#include <memory>

#include "amcr/recognizer.h"
#include "baselines/baseline.h"

namespace amcr_bench
{
class AmcrMethod : public Method
{
public:
  AmcrMethod(const amcr::Params& params, std::shared_ptr<const amcr::PrototypeMemory> memory)
    : recognizer_(params, std::move(memory))
  {
  }
  std::string name() const override { return "amcr"; }
  void reset() override { recognizer_.reset(); }
  std::vector<Detection> detect(const cv::Mat& grey) override
  {
    std::vector<Detection> found;
    last_ = recognizer_.step(grey);
    for (const amcr::RecognizedObject& o : last_.objects)
    {
      Detection d;
      d.label = o.label;
      d.score = o.score;
      d.prototype_to_image = o.prototype_to_image;
      d.track_id = o.track_id;
      d.state = amcr::toString(o.state);
      for (const amcr::Correspondence& c : o.correspondences)
        d.correspondences.push_back({c.image, c.prototype});
      found.push_back(std::move(d));
    }
    return found;  // in the recognizer's order: best score first
  }

  /// The recognizer and its last step's result, for the recall funnel (recall_funnel.h).
  const amcr::Recognizer& recognizer() const { return recognizer_; }
  const amcr::RecognitionResult& lastResult() const { return last_; }

private:
  amcr::Recognizer recognizer_;
  amcr::RecognitionResult last_;
};
}  // namespace amcr_bench
