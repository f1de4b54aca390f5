#include "amcr/scan/edge_thresholds.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <vector>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
using Histogram = std::array<int, 256>;

/// The grey level below which `quantile` of the histogram's `count` pixels lie.
int quantileOf(const Histogram& h, int count, double quantile)
{
  const int wanted = std::max(1, static_cast<int>(quantile * count));
  int seen = 0;
  for (int g = 0; g < 256; ++g)
  {
    seen += h[g];
    if (seen >= wanted)
      return g;
  }
  return 255;
}
}  // namespace

double stepNoiseSigma(const cv::Mat& smoothed)
{
  if (smoothed.type() != CV_8UC1)
    throw InputError("stepNoiseSigma needs an 8-bit grey image, got " + cv::typeToString(smoothed.type()));
  Histogram h{};
  int count = 0;
  for (int y = 0; y < smoothed.rows; y += 4)
  {
    const uchar* row = smoothed.ptr<uchar>(y);
    for (int x = 1; x + 1 < smoothed.cols; ++x)
    {
      ++h[std::abs(row[x + 1] - row[x - 1])];
      ++count;
    }
  }
  if (count == 0)
    return 0.0;
  // The median of |N(0, s^2)| is 0.6745 s. The steps are whole grey levels:
  // step g stands for [g - 0.5, g + 0.5) (0 for [0, 0.5)), and the median is
  // interpolated within its bin.
  const double half = 0.5 * count;
  int seen = 0;
  for (int g = 0; g < 256; ++g)
  {
    if (seen + h[g] >= half)
    {
      const double from = g == 0 ? 0.0 : g - 0.5, width = g == 0 ? 0.5 : 1.0;
      return (from + width * (half - seen) / std::max(1, h[g])) / 0.6745;
    }
    seen += h[g];
  }
  return 255.0 / 0.6745;
}

EdgeThresholds::EdgeThresholds(double threshold)
  : full_(static_cast<float>(threshold)), lowest_(static_cast<float>(threshold))
{
}

EdgeThresholds::EdgeThresholds(const cv::Mat& smoothed, double threshold, double full_strength)
  : EdgeThresholds(threshold)
{
  if (smoothed.type() != CV_8UC1)
    throw InputError("EdgeThresholds needs an 8-bit grey image, got " + cv::typeToString(smoothed.type()));
  if (full_strength <= 0.0 || smoothed.rows < 3 || smoothed.cols < 3)
    return;
  step_noise_ = static_cast<float>(stepNoiseSigma(smoothed));
  const double floor = std::min(threshold, kNoiseSigmas * step_noise_);
  const int cols = (smoothed.cols + kTile - 1) / kTile, rows = (smoothed.rows + kTile - 1) / kTile;
  // A histogram per tile of the 2 px steps, the larger of the horizontal
  // and the vertical one (the border pixels left out).
  std::vector<Histogram> tiles(static_cast<std::size_t>(rows) * cols, Histogram{});
  for (int y = 1; y + 1 < smoothed.rows; ++y)
  {
    const uchar* above = smoothed.ptr<uchar>(y - 1);
    const uchar* row = smoothed.ptr<uchar>(y);
    const uchar* below = smoothed.ptr<uchar>(y + 1);
    Histogram* tile_row = &tiles[static_cast<std::size_t>(y / kTile) * cols];
    for (int x = 1; x + 1 < smoothed.cols; ++x)
      ++tile_row[x / kTile][std::max(std::abs(row[x + 1] - row[x - 1]), std::abs(below[x] - above[x]))];
  }
  // The strength of each tile's 3 x 3 neighbourhood (rays reach beyond
  // their tile), scaled: full_strength gives the full threshold.
  grid_.create(rows, cols, CV_32F);
  lowest_ = full_;
  for (int ty = 0; ty < rows; ++ty)
    for (int tx = 0; tx < cols; ++tx)
    {
      Histogram h{};
      int count = 0;
      for (int y = std::max(0, ty - 1); y <= std::min(rows - 1, ty + 1); ++y)
        for (int x = std::max(0, tx - 1); x <= std::min(cols - 1, tx + 1); ++x)
        {
          const Histogram& t = tiles[static_cast<std::size_t>(y) * cols + x];
          for (int g = 0; g < 256; ++g)
          {
            h[g] += t[g];
            count += t[g];
          }
        }
      const double strength = count > 0 ? quantileOf(h, count, kStrengthQuantile) : 0.0;
      const float t = static_cast<float>(std::min(threshold, std::max(floor, threshold * strength / full_strength)));
      grid_.at<float>(ty, tx) = t;
      lowest_ = std::min(lowest_, t);
    }
}
}  // namespace amcr
