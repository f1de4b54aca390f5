#include "baseline.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace amcr_bench
{
bool fitAffine(const std::vector<cv::Point2d>& from, const std::vector<cv::Point2d>& to, cv::Matx23d& out)
{
  if (from.size() < 3 || from.size() != to.size())
    return false;
  cv::Mat a(static_cast<int>(from.size()), 3, CV_64F);
  cv::Mat b(static_cast<int>(from.size()), 2, CV_64F);
  for (int i = 0; i < a.rows; ++i)
  {
    a.at<double>(i, 0) = from[i].x;
    a.at<double>(i, 1) = from[i].y;
    a.at<double>(i, 2) = 1.0;
    b.at<double>(i, 0) = to[i].x;
    b.at<double>(i, 1) = to[i].y;
  }
  cv::Mat x;
  if (!cv::solve(a, b, x, cv::DECOMP_SVD))
    return false;
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
      out(r, c) = x.at<double>(c, r);
  return std::abs(out(0, 0) * out(1, 1) - out(0, 1) * out(1, 0)) > 1e-9;
}

cv::Mat normalisedPrototype(const cv::Mat& mask, int longer, int border, cv::Matx23d& to_original)
{
  const double scale = static_cast<double>(longer) / std::max(mask.cols, mask.rows);
  cv::Mat scaled;
  cv::resize(mask, scaled, cv::Size(), scale, scale, scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::copyMakeBorder(scaled, scaled, border, border, border, border, cv::BORDER_CONSTANT, 0);
  // Pixel centres: original x = (scaled x - border + 0.5) / scale - 0.5.
  to_original = cv::Matx23d(1 / scale, 0, (-border + 0.5) / scale - 0.5, 0, 1 / scale, (-border + 0.5) / scale - 0.5);
  return scaled;
}
}  // namespace amcr_bench
