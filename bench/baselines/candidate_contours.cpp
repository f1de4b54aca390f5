#include "candidate_contours.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace amcr_bench
{
std::vector<cv::Point> prototypeOutline(const cv::Mat& mask)
{
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask > 127, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  if (contours.empty())
    return {};
  return *std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
}

std::vector<std::vector<cv::Point>> candidateContours(const cv::Mat& grey, int adaptive_block, double adaptive_c,
                                                      int clean_px)
{
  std::vector<cv::Mat> binaries(4);
  cv::threshold(grey, binaries[0], 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  cv::threshold(grey, binaries[1], 0, 255, cv::THRESH_BINARY_INV | cv::THRESH_OTSU);
  cv::adaptiveThreshold(grey, binaries[2], 255, cv::ADAPTIVE_THRESH_MEAN_C, cv::THRESH_BINARY, adaptive_block,
                        -adaptive_c);
  cv::adaptiveThreshold(grey, binaries[3], 255, cv::ADAPTIVE_THRESH_MEAN_C, cv::THRESH_BINARY_INV, adaptive_block,
                        adaptive_c);
  std::vector<std::vector<cv::Point>> all;
  for (cv::Mat& binary : binaries)
  {
    if (clean_px > 1)
    {
      const cv::Mat disc = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(clean_px, clean_px));
      cv::morphologyEx(binary, binary, cv::MORPH_OPEN, disc);
      cv::morphologyEx(binary, binary, cv::MORPH_CLOSE, disc);
    }
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(binary, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    all.insert(all.end(), contours.begin(), contours.end());
  }
  return all;
}
}  // namespace amcr_bench
