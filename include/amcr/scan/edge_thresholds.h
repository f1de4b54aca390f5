// Edge thresholds relative to local contrast. edge_threshold is the step
// over 2 px that makes an edge where the strongest edges around a point step
// by edge_full_strength or more; where they are weaker (a faint print, a dim
// corner of the room, a defocused view) the threshold falls in proportion,
// so the outline of a shape printed 40 grey levels off its background and
// out of focus is still an edge (as Canny's thresholds are often set from
// the gradient's quantiles, here per region). It never falls below
// kNoiseSigmas times the frame's step noise, so flat regions stay flat. The
// strength is measured on tiles of kTile px; a point's threshold is
// interpolated between the tile centres.
#pragma once

#include <algorithm>

#include <opencv2/core.hpp>

namespace amcr
{
class EdgeThresholds
{
public:
  /// Side of a contrast tile, working px.
  static constexpr int kTile = 32;
  /// The edge strength of a tile is this quantile of the 2 px steps over
  /// its 3 x 3 tile neighbourhood (about 100 px square): the top percent
  /// is the strongest band of an edge some 30 px long or more.
  static constexpr double kStrengthQuantile = 0.99;
  /// The lowest threshold, in multiples of the frame's step noise: a
  /// Gaussian step exceeds 5 sigma once in about 1.7 million samples.
  static constexpr double kNoiseSigmas = 5.0;

  /// `threshold` everywhere.
  explicit EdgeThresholds(double threshold);

  /// Thresholds for the smoothed 8-bit image `smoothed` (the scan image):
  /// `threshold` where the local edge strength reaches `full_strength` grey
  /// levels, less in proportion below it, never below the noise floor.
  /// full_strength 0 gives `threshold` everywhere. Throws InputError for an
  /// image that is not CV_8UC1.
  EdgeThresholds(const cv::Mat& smoothed, double threshold, double full_strength);

  /// The threshold at (x, y), px of the image.
  float at(float x, float y) const
  {
    if (grid_.empty())
      return full_;
    const float gx = clampTo(x * inv_tile_ - 0.5f, grid_.cols - 1), gy = clampTo(y * inv_tile_ - 0.5f, grid_.rows - 1);
    const int x0 = static_cast<int>(gx), y0 = static_cast<int>(gy);
    const int x1 = std::min(x0 + 1, grid_.cols - 1), y1 = std::min(y0 + 1, grid_.rows - 1);
    const float fx = gx - x0, fy = gy - y0;
    const float* r0 = grid_.ptr<float>(y0);
    const float* r1 = grid_.ptr<float>(y1);
    const float top = r0[x0] + fx * (r0[x1] - r0[x0]);
    const float bottom = r1[x0] + fx * (r1[x1] - r1[x0]);
    return top + fy * (bottom - top);
  }

  /// The threshold at full contrast (edge_threshold).
  float full() const { return full_; }
  /// The lowest threshold of the frame (full() when uniform).
  float lowest() const { return lowest_; }
  /// The frame's step noise (robust sigma of the 2 px steps), grey levels; 0 when uniform.
  float stepNoise() const { return step_noise_; }
  /// The thresholds per tile (CV_32F), empty when uniform.
  const cv::Mat& grid() const { return grid_; }

private:
  /// v within [0, hi]; NaN (a point mapped by a degenerate transform) gives 0.
  static float clampTo(float v, int hi)
  {
    return v > 0.f ? (v < static_cast<float>(hi) ? v : static_cast<float>(hi)) : 0.f;
  }

  cv::Mat grid_;
  float full_ = 0.f;
  float lowest_ = 0.f;
  float step_noise_ = 0.f;
  float inv_tile_ = 1.f / kTile;
};

/// The robust sigma of the 2 px steps |I(x+1) - I(x-1)| of an 8-bit image
/// along its rows (median / 0.6745, over every 4th row): in a frame that is
/// mostly flat, the noise of what a ray compares with the threshold.
double stepNoiseSigma(const cv::Mat& smoothed);
}  // namespace amcr
