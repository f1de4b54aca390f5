#include "hu_moments.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "candidate_contours.h"

namespace amcr_bench
{
namespace
{
/// Centroid, and the principal axes scaled by their standard deviations (columns of `axes`).
bool frameOf(const std::vector<cv::Point>& contour, cv::Point2d& centre, cv::Matx22d& axes)
{
  const cv::Moments m = cv::moments(contour);
  if (std::abs(m.m00) < 1e-9)
    return false;
  centre = {m.m10 / m.m00, m.m01 / m.m00};
  const cv::Matx22d cov(m.mu20 / m.m00, m.mu11 / m.m00, m.mu11 / m.m00, m.mu02 / m.m00);
  cv::Mat values, vectors;
  cv::eigen(cv::Mat(cov), values, vectors);  // rows of `vectors`, largest value first
  for (int k = 0; k < 2; ++k)
  {
    double ex = vectors.at<double>(k, 0), ey = vectors.at<double>(k, 1);
    const double skew = ex * ex * ex * m.mu30 + 3 * ex * ex * ey * m.mu21 + 3 * ex * ey * ey * m.mu12 + ey * ey * ey * m.mu03;
    if (skew < 0)
    {
      ex = -ex;
      ey = -ey;
    }
    const double sd = std::sqrt(std::max(values.at<double>(k), 1e-12));
    axes(0, k) = ex * sd;
    axes(1, k) = ey * sd;
  }
  return true;
}
}  // namespace

bool affineFromMoments(const std::vector<cv::Point>& from, const std::vector<cv::Point>& to, cv::Matx23d& out)
{
  cv::Point2d cf, ct;
  cv::Matx22d af, at;
  if (!frameOf(from, cf, af) || !frameOf(to, ct, at) || std::abs(cv::determinant(af)) < 1e-12)
    return false;
  const cv::Matx22d linear = at * af.inv();
  const cv::Vec2d offset = cv::Vec2d(ct.x, ct.y) - linear * cv::Vec2d(cf.x, cf.y);
  out = cv::Matx23d(linear(0, 0), linear(0, 1), offset[0], linear(1, 0), linear(1, 1), offset[1]);
  return true;
}

HuMoments::HuMoments(const std::vector<PrototypeImage>& prototypes, const HuConfig& config) : config_(config)
{
  for (const PrototypeImage& p : prototypes)
  {
    std::vector<cv::Point> outline = prototypeOutline(p.mask);
    if (outline.empty())
      continue;
    models_.push_back({p.label, std::move(outline)});
  }
}

std::vector<Detection> HuMoments::detect(const cv::Mat& grey)
{
  const double max_area = config_.max_area_share * grey.total();

  // Per prototype, its best contour below the distance limit.
  std::vector<double> best(models_.size(), std::numeric_limits<double>::infinity());
  std::vector<std::vector<cv::Point>> best_contour(models_.size());
  std::vector<int> best_id(models_.size(), -1);  // which contour, to report each at most once
  int id = 0;
  for (const auto& contour : candidateContours(grey, config_.adaptive_block, config_.adaptive_c))
  {
    ++id;
    const double area = cv::contourArea(contour);
    if (area < config_.min_area || area > max_area)
      continue;
    for (std::size_t i = 0; i < models_.size(); ++i)
    {
      const double d = cv::matchShapes(models_[i].contour, contour, cv::CONTOURS_MATCH_I1, 0);
      if (d < best[i])
      {
        best[i] = d;
        best_contour[i] = contour;
        best_id[i] = id;
      }
    }
  }
  // One contour explains one object: the prototype that matches it best.
  std::vector<Detection> found;
  for (std::size_t i = 0; i < models_.size(); ++i)
  {
    if (!(best[i] <= config_.max_distance))
      continue;
    bool beaten = false;
    for (std::size_t j = 0; j < models_.size(); ++j)
      beaten |= j != i && best_id[j] == best_id[i] && (best[j] < best[i] || (best[j] == best[i] && j < i));
    if (beaten)
      continue;
    Detection d;
    if (!affineFromMoments(models_[i].contour, best_contour[i], d.prototype_to_image))
      continue;
    d.label = models_[i].label;
    d.score = -best[i];
    found.push_back(std::move(d));
  }
  std::sort(found.begin(), found.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
  return found;
}
}  // namespace amcr_bench
