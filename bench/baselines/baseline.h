// What every recognizer of the benchmark gets and answers: the same prototypes
// (a white silhouette on black, or a grey template, as in the memory folder) and
// one grey frame at a time; per frame a list of detections, best first.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace amcr_bench
{
struct PrototypeImage
{
  PrototypeImage() = default;
  PrototypeImage(std::string label_, cv::Mat mask_, cv::Mat grey_ = cv::Mat())
    : label(std::move(label_)), mask(std::move(mask_)), grey(std::move(grey_))
  {
  }

  std::string label;
  /// 8-bit, shape > 127: a silhouette as the file holds it; for a grey template its region (255 where
  /// the template is), the shape that the methods which know only silhouettes take.
  cv::Mat mask;
  /// A grey template (amcr reads the file as one: prototype_file.h) as 8-bit grey, the size of `mask`;
  /// empty for a silhouette.
  cv::Mat grey;
  bool isTemplate() const { return !grey.empty(); }
};

struct Detection
{
  std::string label;
  double score = 0.0;             ///< the method's own confidence (higher is better)
  cv::Matx23d prototype_to_image;  ///< original prototype px -> image px (pixel centres)
  /// The method's track of this object, stable from frame to frame; -1: the method keeps no tracks
  /// (the baselines), and the JSONL line omits it.
  int track_id = -1;
  /// Where the track is in its life cycle ("tentative", "confirmed", "held"); with a track only.
  std::string state;
  /// Pairs (image point, prototype point), when the method has them.
  std::vector<std::pair<cv::Point2d, cv::Point2d>> correspondences;
};

class Method
{
public:
  virtual ~Method() = default;
  virtual std::string name() const = 0;
  /// Forgets any state between sequences.
  virtual void reset() {}
  virtual std::vector<Detection> detect(const cv::Mat& grey) = 0;
};

/// The prototype scaled so that its longer side is `longer` px, with a `border` of black
/// around it; `to_original` maps the scaled image's pixels back to the original's.
cv::Mat normalisedPrototype(const cv::Mat& mask, int longer, int border, cv::Matx23d& to_original);
}  // namespace amcr_bench
