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
    for (const amcr::RecognizedObject& o : recognizer_.step(grey).objects)
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

private:
  amcr::Recognizer recognizer_;
};
}  // namespace amcr_bench
