// Baseline: OpenCV's GeneralizedHoughGuil (rotation and scale) on the prototype's edges,
// one detector per prototype and print polarity (Guil's features use the gradient
// direction, so a dark-on-light template does not find a light-on-dark print); the
// detection with the most position votes per template edge point wins. It models a similarity only: shear and
// anisotropic scale are out of its reach by design.
#pragma once

#include <vector>

#include <opencv2/imgproc.hpp>

#include "baseline.h"

namespace amcr_bench
{
struct HoughConfig
{
  int template_side = 160;  ///< prototypes rescaled to this longer side, px
  double min_scale = 0.5;   ///< template scale range in the frame
  double max_scale = 2.0;
  double scale_step = 0.05;
  double angle_step = 2.0;  ///< degrees, over the full circle
  int canny_low = 50;
  int canny_high = 100;
  // Guil's vote thresholds, as shares of the template's edge points (votes grow with them);
  // set by hand on clean rotated, scaled copies of a prototype and on one cluttered frame:
  // lower ones take tens of seconds per prototype on clutter, higher ones miss the copies.
  double angle_votes = 0.2;
  double scale_votes = 0.04;
  double position_votes = 0.02;
  double report_votes = 0.03;  ///< position votes per edge point a detection needs to be reported
};

class GeneralizedHough : public Method
{
public:
  GeneralizedHough(const std::vector<PrototypeImage>& prototypes, const HoughConfig& config = HoughConfig());
  std::string name() const override { return "ght"; }
  std::vector<Detection> detect(const cv::Mat& grey) override;

private:
  struct Model
  {
    std::string label;
    std::vector<cv::Ptr<cv::GeneralizedHoughGuil>> detectors;  ///< dark on light, light on dark
    cv::Matx23d template_to_original;
    cv::Point2d centre;  ///< template centre that the detectors locate, template px
    int edge_points = 1;  ///< of the template: votes are compared per edge point
  };
  HoughConfig config_;
  std::vector<Model> models_;
};
}  // namespace amcr_bench
