// Radial edge scans (spec "Radial edge scans"): from a point, walk a ray until
// the first grey-level step above a threshold. Used on the input image by
// the V-particles and, once, on each prototype to build its lookup table.
#pragma once

#include <algorithm>
#include <cstddef>

#include <opencv2/core.hpp>

#include "amcr/scan/edge_thresholds.h"

namespace amcr
{
/// Result of one ray: the distance to the first edge along the ray, or
/// invalid when no edge is met within the maximal length or the image.
struct RayHit
{
  bool valid = false;
  float distance = 0.f;  ///< px from the ray's origin to the edge
};

/// Scans rays in one smoothed 8-bit grey image. The image is borrowed: it
/// must outlive the scanner.
class RadialScanner
{
public:
  /// `smoothed` is CV_8UC1 (already blurred); `threshold` is the grey-level
  /// difference between the samples 1 px before and 1 px after a point that
  /// makes it an edge; `max_length` in px.
  RadialScanner(const cv::Mat& smoothed, double threshold, double max_length);

  /// The same, with a map of free space (CV_32FC1, the image's size): from
  /// pixel q, no ray step within free_space(q) px reaches the threshold, so
  /// the scan leaps over it. Used for the prototype lookup tables, where the
  /// map comes from a distance transform; a scan gives the same hit with or
  /// without it.
  RadialScanner(const cv::Mat& smoothed, double threshold, double max_length, const cv::Mat& free_space);

  /// The same with thresholds that follow the local contrast
  /// (edge_thresholds.h): a ray uses the threshold at its origin.
  RadialScanner(const cv::Mat& smoothed, const EdgeThresholds& thresholds, double max_length);

  /// First edge along the ray from (x, y) in direction (dx, dy), |(dx,dy)| = 1,
  /// by the threshold at (x, y). The edge is placed at the largest step of the first run of samples above
  /// the threshold, refined to sub-pixel by a parabola.
  RayHit scan(float x, float y, float dx, float dy) const;

  /// Convenience: scan at an angle in rad (x right, y down).
  RayHit scanAngle(float x, float y, double angle) const;

  /// Unit normal of the intensity edge at (x, y) from the image gradient
  /// (pointing towards increasing grey), or (0, 0) where the gradient is flat.
  cv::Point2f edgeNormal(float x, float y) const;

  /// Bilinear grey level at (x, y); (x, y) must lie in [0, cols-1] x [0, rows-1].
  float sample(float x, float y) const
  {
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const int dx = x0 + 1 < cols_ ? 1 : 0;
    const std::size_t dy = y0 + 1 < rows_ ? step_ : 0;
    const float fx = x - x0, fy = y - y0;
    const uchar* p = data_ + static_cast<std::size_t>(y0) * step_ + x0;
    const float top = p[0] + fx * (p[dx] - p[0]);
    const float bottom = p[dy] + fx * (p[dy + dx] - p[dy]);
    return top + fy * (bottom - top);
  }

  /// Whether (x, y) lies where sample() may be called.
  bool contains(float x, float y) const { return x >= 0.f && y >= 0.f && x <= max_x_ && y <= max_y_; }

  /// The threshold at full contrast (edge_threshold).
  double threshold() const { return thresholds_.full(); }
  /// The threshold at (x, y) (threshold() unless it follows the local contrast).
  float threshold(float x, float y) const { return thresholds_.at(x, y); }
  const EdgeThresholds& thresholds() const { return thresholds_; }

  const cv::Mat& image() const { return image_; }

private:
  /// The edge of the run of steps above the threshold that starts at t (scan()).
  RayHit peakOfRun(float x, float y, float dx, float dy, int t, int steps, float last_step, float step, float current,
                   float next) const;
  void checkInputs();

  /// Whole px of free space at (x, y) (0 without a map).
  int leap(float x, float y) const
  {
    if (!free_)
      return 0;
    const int ix = std::min(static_cast<int>(x + 0.5f), cols_ - 1), iy = std::min(static_cast<int>(y + 0.5f), rows_ - 1);
    return static_cast<int>(free_[static_cast<std::size_t>(iy) * cols_ + ix]);
  }

  cv::Mat image_;
  cv::Mat free_space_;
  // Raw views of image_ and free_space_ for the inner loops.
  const uchar* data_ = nullptr;
  std::size_t step_ = 0;
  int cols_ = 0;
  int rows_ = 0;
  float max_x_ = 0.f;
  float max_y_ = 0.f;
  const float* free_ = nullptr;
  EdgeThresholds thresholds_;
  float max_length_;
};

/// Converts any supported image to the scanner's input: 8-bit grey, smoothed
/// with a Gaussian of `blur_sigma` px (0: no smoothing). Accepts CV_8U/16U/32F
/// with 1, 3 (BGR) or 4 (BGRA) channels; throws InputError naming the type
/// otherwise, and for an empty image.
cv::Mat prepareScanImage(const cv::Mat& image, double blur_sigma);

/// Converts to 8-bit grey without smoothing (the same rules as prepareScanImage).
cv::Mat toGray8(const cv::Mat& image);
}  // namespace amcr
