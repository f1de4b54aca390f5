#include "amcr/memory/edge_model_picture.h"

#include <algorithm>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace amcr
{
cv::Mat drawEdgeModel(const Prototype& prototype, int scale)
{
  scale = std::max(1, scale);
  cv::Mat grey, picture;
  prototype.scanImage().convertTo(grey, CV_8U, 0.5, 64);  // dimmed, so that the model stands out
  cv::resize(grey, grey, cv::Size(), scale, scale, cv::INTER_NEAREST);
  cv::cvtColor(grey, picture, cv::COLOR_GRAY2BGR);
  std::vector<std::vector<cv::Point>> region;
  cv::findContours(prototype.mask().clone(), region, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  for (auto& contour : region)
    for (cv::Point& p : contour)
      p = p * scale + cv::Point(scale / 2, scale / 2);
  cv::polylines(picture, region, true, cv::Scalar(255, 160, 0), 1, cv::LINE_AA);
  const double s = scale;
  for (const OutlinePoint& o : prototype.outline())
  {
    const cv::Point2d at((o.position.x + 0.5) * s, (o.position.y + 0.5) * s);
    const cv::Point2d tip = at + 1.5 * s * cv::Point2d(o.normal.x, o.normal.y);
    cv::line(picture, at, tip, cv::Scalar(0, 200, 255), 1, cv::LINE_AA);
    cv::circle(picture, at, std::max(1, scale / 2), cv::Scalar(0, 0, 255), cv::FILLED, cv::LINE_AA);
  }
  return picture;
}
}  // namespace amcr
