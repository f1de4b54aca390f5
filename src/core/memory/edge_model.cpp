#include "amcr/memory/edge_model.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/scan/edge_thresholds.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
namespace
{
constexpr double kLevelBand = 0.1;  // share of the contrast around each level that still counts as that level
constexpr int kThinningCell = 2;   // one edge point per cell x cell pixels: about the outline's 2 px spacing

/// Grey gradient (per px) at every pixel: Sobel's 3 x 3 derivative over its weight 8.
void greyGradient(const cv::Mat& image, cv::Mat& gx, cv::Mat& gy)
{
  cv::Sobel(image, gx, CV_32F, 1, 0, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
  cv::Sobel(image, gy, CV_32F, 0, 1, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
}

float bilinear(const cv::Mat& m, float x, float y)
{
  x = std::clamp(x, 0.f, static_cast<float>(m.cols - 1));
  y = std::clamp(y, 0.f, static_cast<float>(m.rows - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, m.cols - 1), y1 = std::min(y0 + 1, m.rows - 1);
  const float fx = x - x0, fy = y - y0;
  const float top = m.at<float>(y0, x0) + fx * (m.at<float>(y0, x1) - m.at<float>(y0, x0));
  const float bottom = m.at<float>(y1, x0) + fx * (m.at<float>(y1, x1) - m.at<float>(y1, x0));
  return top + fy * (bottom - top);
}
}  // namespace

bool isSilhouette(const cv::Mat& grey)
{
  CV_Assert(grey.type() == CV_8UC1);
  cv::Mat split;
  cv::threshold(grey, split, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const int high_count = cv::countNonZero(split);
  if (high_count == 0 || high_count == static_cast<int>(grey.total()))
    return false;  // one grey level: no shape
  const double high = cv::mean(grey, split)[0], low = cv::mean(grey, ~split)[0];
  const double band = kLevelBand * (high - low);
  long elsewhere = 0;
  for (int y = 0; y < grey.rows; ++y)
  {
    const std::uint8_t* row = grey.ptr<std::uint8_t>(y);
    for (int x = 0; x < grey.cols; ++x)
      elsewhere += (std::abs(row[x] - low) > band && std::abs(row[x] - high) > band) ? 1 : 0;
  }
  return static_cast<double>(elsewhere) <= kSilhouetteMidShare * static_cast<double>(grey.total());
}

std::vector<OutlinePoint> templateEdgePoints(const cv::Mat& scan_image, double edge_threshold, double full_strength,
                                             int min_length, const cv::Mat& region)
{
  CV_Assert(scan_image.type() == CV_8UC1);
  const EdgeThresholds thresholds(scan_image, edge_threshold, full_strength);
  cv::Mat gx, gy, magnitude;
  greyGradient(scan_image, gx, gy);
  cv::magnitude(gx, gy, magnitude);

  // Non-maximum suppression along the gradient; the scanner's edge is a step
  // I(t + 1) - I(t - 1), twice the gradient.
  cv::Mat edges = cv::Mat::zeros(scan_image.size(), CV_8UC1);
  cv::Mat offset = cv::Mat::zeros(scan_image.size(), CV_32F);
  for (int y = 1; y + 1 < scan_image.rows; ++y)
    for (int x = 1; x + 1 < scan_image.cols; ++x)
    {
      const float g = magnitude.at<float>(y, x);
      if (2.f * g < thresholds.at(static_cast<float>(x), static_cast<float>(y)) || g <= 0.f)
        continue;
      if (!region.empty() && region.at<std::uint8_t>(y, x) == 0)
        continue;
      const float nx = gx.at<float>(y, x) / g, ny = gy.at<float>(y, x) / g;
      const float before = bilinear(magnitude, x - nx, y - ny), after = bilinear(magnitude, x + nx, y + ny);
      if (g < before || g <= after)
        continue;
      edges.at<std::uint8_t>(y, x) = 255;
      // The parabola's vertex through (-1, before), (0, g), (1, after): within half a pixel.
      const float curvature = before - 2.f * g + after;
      offset.at<float>(y, x) = curvature < 0.f ? std::clamp(0.5f * (before - after) / curvature, -0.5f, 0.5f) : 0.f;
    }

  // Chains shorter than min_length pixels are texture or noise, not the part's shape.
  cv::Mat labels, stats, centroids;
  const int chains = cv::connectedComponentsWithStats(edges, labels, stats, centroids, 8, CV_32S);
  std::vector<bool> long_enough(chains, false);
  for (int c = 1; c < chains; ++c)
    long_enough[c] = stats.at<int>(c, cv::CC_STAT_AREA) >= min_length;

  // The strongest edge pixel of each cell, so that points are as dense as a silhouette's outline.
  std::vector<OutlinePoint> points;
  for (int cy = 0; cy < scan_image.rows; cy += kThinningCell)
    for (int cx = 0; cx < scan_image.cols; cx += kThinningCell)
    {
      float best = 0.f;
      cv::Point at(-1, -1);
      for (int y = cy; y < std::min(cy + kThinningCell, scan_image.rows); ++y)
        for (int x = cx; x < std::min(cx + kThinningCell, scan_image.cols); ++x)
          if (edges.at<std::uint8_t>(y, x) && long_enough[labels.at<int>(y, x)] && magnitude.at<float>(y, x) > best)
          {
            best = magnitude.at<float>(y, x);
            at = {x, y};
          }
      if (at.x < 0)
        continue;
      const cv::Point2f normal(gx.at<float>(at) / best, gy.at<float>(at) / best);
      points.push_back({cv::Point2f(static_cast<float>(at.x), static_cast<float>(at.y)) + offset.at<float>(at) * normal,
                        normal});
    }
  return points;
}

void prototypeGreyAndAlpha(const cv::Mat& image, cv::Mat& grey, cv::Mat& alpha)
{
  grey = toGray8(image);
  alpha.release();
  if (image.channels() == 4)
  {
    cv::extractChannel(image, alpha, 3);
    alpha = toGray8(alpha);
    if (cv::countNonZero(alpha < 128) == 0)
      alpha.release();
  }
}

bool readAsTemplate(const cv::Mat& grey, const cv::Mat& alpha) { return !alpha.empty() || !isSilhouette(grey); }
}  // namespace amcr
