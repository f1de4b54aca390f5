#include "baseline.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace amcr_bench
{
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
