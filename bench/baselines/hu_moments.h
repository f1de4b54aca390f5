// Baseline: Hu-moment contour matching. The frame is binarised (Otsu and adaptive,
// both polarities), every contour of a plausible size is compared with every
// prototype's outline by cv::matchShapes (CONTOURS_MATCH_I1), and the affine
// comes from the moments (centroid, principal axes, third-order skew for the signs).
#pragma once

#include <vector>

#include "baseline.h"

namespace amcr_bench
{
struct HuConfig
{
  double max_distance = 0.05;  ///< matchShapes I1 distance accepted as a match
  double min_area = 800.0;     ///< contour area range, px^2
  double max_area_share = 0.4; ///< of the frame
  int adaptive_block = 51;     ///< adaptive-threshold block, px
  double adaptive_c = 10.0;
};

class HuMoments : public Method
{
public:
  HuMoments(const std::vector<PrototypeImage>& prototypes, const HuConfig& config = HuConfig());
  std::string name() const override { return "hu"; }
  std::vector<Detection> detect(const cv::Mat& grey) override;

private:
  struct Model
  {
    std::string label;
    std::vector<cv::Point> contour;
  };
  HuConfig config_;
  std::vector<Model> models_;
};

/// The affine taking the region of `from` onto the region of `to` that the moments imply:
/// centroids matched, principal axes and their spreads matched, axis signs by third-order skew.
bool affineFromMoments(const std::vector<cv::Point>& from, const std::vector<cv::Point>& to, cv::Matx23d& out);
}  // namespace amcr_bench
