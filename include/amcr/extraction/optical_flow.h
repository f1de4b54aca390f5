// Pyramidal Lucas-Kanade flow at a sparse set of points (spec "Tracking"):
// the V-particles ride the flow so each stays on the same object point while
// the object moves. The pyramid of each frame is built once and kept as the
// previous pyramid of the next frame.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace amcr
{
/// One point's flow between the previous and the current frame.
struct FlowVector
{
  cv::Point2f to;     ///< position in the current frame, px
  bool ok = false;    ///< false: not found, too large an error, or left the image
  /// false: Lucas-Kanade found no flow there at all (its window too flat to
  /// track, or off the image), as opposed to a flow whose window does not
  /// match the new frame (too large an error: occlusion, a new scene)
  bool found = false;
};

class PyramidFlow
{
public:
  /// `window`: side of the LK window, px; `levels`: pyramid levels above the
  /// frame; `max_error`: largest mean absolute grey-level difference over the
  /// window for a flow to count as found.
  PyramidFlow(int window, int levels, double max_error);

  /// Takes the next frame (8-bit grey): the current pyramid becomes the
  /// previous one. A frame of another size forgets the previous pyramid.
  void push(const cv::Mat& gray8);

  /// Whether flow can be computed (two frames of the same size were pushed).
  bool ready() const { return !previous_.empty(); }

  /// Flow of `from` (previous-frame px) into the current frame; empty when
  /// not ready().
  std::vector<FlowVector> track(const std::vector<cv::Point2f>& from) const;

  /// Forgets both pyramids.
  void reset();

private:
  cv::Size window_;
  int levels_;
  double max_error_;
  cv::Size frame_size_;
  std::vector<cv::Mat> previous_;
  std::vector<cv::Mat> current_;
};

/// The motion of a rigid patch between two frames estimated from point flows:
/// a similarity (rotation, uniform scale, translation) fitted with RANSAC to
/// the pairs whose flow is ok. False when fewer than `min_inliers` agree.
bool estimatePatchMotion(const std::vector<cv::Point2f>& from, const std::vector<FlowVector>& flow,
                         int min_inliers, cv::Matx23d& motion);
}  // namespace amcr
