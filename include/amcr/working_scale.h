// Resolution independence: the filter works on the input
// reduced to params.working_resolution (its longer side), so that the rays,
// steps and seeding, which are in px, see objects of the same size whatever
// the camera's resolution. Everything a user gets back is mapped to input px.
#pragma once

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/extraction/recognition_result.h"

namespace amcr
{
/// The map between an input image and the working image the filter sees.
/// Both are in OpenCV's pixel-centre convention, as cv::resize maps them:
/// x_input = (x_working + 0.5) * input.width / working.width - 0.5 (and y).
struct WorkingScale
{
  cv::Size input;
  cv::Size working;

  /// True when the working image is the input itself (nothing to map).
  bool identity() const { return input == working; }
  /// Working px per input px along the longer side (1 for the identity).
  double factor() const;
  /// Working px -> input px.
  Affine toInput() const;
  /// Input px -> working px.
  Affine toWorking() const;
};

/// The working size of an input: its longer side reduced to
/// `working_resolution` px, the aspect ratio kept (each side rounded, at least
/// 1 px); the input itself when `working_resolution` is 0 or the input is not
/// larger (an image is never enlarged: that adds no detail, only cost).
WorkingScale chooseWorkingScale(const cv::Size& input, int working_resolution);

/// `grey` (the input) reduced to scale.working with cv::INTER_AREA (each
/// working pixel the mean of the input area it covers: no aliasing of thin
/// edges); `grey` itself when the scale is the identity.
cv::Mat toWorkingImage(const cv::Mat& grey, const WorkingScale& scale);

/// Maps every geometric field of `result` from working px to input px by
/// `working_to_input`: outlines and the image side of correspondences are
/// mapped, the affines and the homography composed with it; anisotropy and
/// viewing angle are recomputed from the new prototype_to_image. Scores,
/// support, labels and ids do not depend on the resolution and stay.
void scaleResult(RecognitionResult& result, const Affine& working_to_input);
}  // namespace amcr
