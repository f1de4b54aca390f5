// Baseline: ORB features, ratio test and a RANSAC homography per prototype, the
// method of find_object_2d (the ROS package users pick for "find this object"): the
// descriptors of all prototypes in one FLANN LSH index, each frame descriptor matched
// to its 2 nearest there (ratio test over the whole memory), then a homography per
// prototype with enough matches.
#pragma once

#include <vector>

#include <opencv2/features2d.hpp>

#include "baseline.h"

namespace amcr_bench
{
struct OrbConfig
{
  int prototype_side = 200;      ///< prototypes rescaled to this longer side before ORB, px
  int prototype_features = 400;  ///< per prototype and polarity
  int frame_features = 1500;
  double ratio = 0.8;            ///< Lowe's ratio test (find_object_2d's NNDR default)
  double ransac_px = 5.0;        ///< RANSAC reprojection threshold, image px
  int min_inliers = 10;          ///< find_object_2d's minimum inliers
};

class OrbHomography : public Method
{
public:
  OrbHomography(const std::vector<PrototypeImage>& prototypes, const OrbConfig& config = OrbConfig());
  std::string name() const override { return "orb"; }
  std::vector<Detection> detect(const cv::Mat& grey) override;

private:
  struct Model
  {
    std::string label;
    cv::Size size;  ///< original prototype size
  };
  OrbConfig config_;
  cv::Ptr<cv::ORB> frame_orb_;
  std::vector<Model> models_;
  // One row per prototype descriptor: its prototype and its point in original prototype px.
  std::vector<int> owner_;
  std::vector<cv::Point2d> points_;
  cv::FlannBasedMatcher matcher_;
};
}  // namespace amcr_bench
