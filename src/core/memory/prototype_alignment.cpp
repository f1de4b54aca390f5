#include "amcr/memory/prototype_alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "amcr/memory/prototype.h"

namespace amcr
{
namespace
{
constexpr int kRefinements = 6;           // outline fits after the robust start
constexpr double kKeptShare = 2.0 / 3.0;  // the nearest outline pairs kept per fit

Affine toAffine(const Eigen::MatrixXd& m)
{
  return Affine(m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2));
}

/// For each point of `from`, the distance to the nearest point of `to` and its index.
void nearestPoints(const std::vector<cv::Point2d>& from, const std::vector<cv::Point2d>& to,
                   std::vector<std::pair<double, int>>& nearest)
{
  nearest.assign(from.size(), {0.0, -1});
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < to.size(); ++j)
    {
      const double dx = from[i].x - to[j].x, dy = from[i].y - to[j].y;
      const double d = dx * dx + dy * dy;
      if (d < best)
      {
        best = d;
        nearest[i] = {d, static_cast<int>(j)};
      }
    }
    nearest[i].first = std::sqrt(best);
  }
}

std::vector<cv::Point2d> outlinePoints(const Prototype& p, const Affine& map)
{
  std::vector<cv::Point2d> out;
  out.reserve(p.outline().size());
  for (const OutlinePoint& o : p.outline())
    out.push_back(applyAffine(map, cv::Point2d(o.position)));
  return out;
}

/// The indices of the kKeptShare of `nearest` with the smallest distances.
std::vector<std::size_t> nearestShare(const std::vector<std::pair<double, int>>& nearest)
{
  std::vector<std::size_t> order(nearest.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  const std::size_t kept =
      std::min(order.size(), std::max<std::size_t>(3, static_cast<std::size_t>(kKeptShare * order.size())));
  std::nth_element(order.begin(), order.begin() + (kept - 1), order.end(), [&nearest](std::size_t i, std::size_t j) {
    return nearest[i].first < nearest[j].first || (nearest[i].first == nearest[j].first && i < j);
  });
  order.resize(kept);
  return order;
}

double medianDistance(std::vector<std::pair<double, int>> nearest)
{
  if (nearest.empty())
    return std::numeric_limits<double>::infinity();
  const auto middle = nearest.begin() + nearest.size() / 2;
  std::nth_element(nearest.begin(), middle, nearest.end());
  return middle->first;
}
}  // namespace

bool alignPrototypes(const Prototype& a, const Prototype& b, const std::vector<cv::Point2d>& in_a,
                     const std::vector<cv::Point2d>& in_b, double tolerance, int min_inliers,
                     double max_outline_distance, PrototypeAlignment& out)
{
  if (in_a.size() != in_b.size() || static_cast<int>(in_a.size()) < std::max(2, min_inliers) ||
      a.outline().size() < 3 || b.outline().size() < 3)
    return false;
  // OpenCV's RANSAC seeds its own generator with a constant on every call:
  // the same places give the same similarity.
  std::vector<uchar> inlier;
  const cv::Mat start = cv::estimateAffinePartial2D(in_a, in_b, inlier, cv::RANSAC, tolerance, 2000, 0.99, 10);
  if (start.empty())
    return false;
  out.inliers = static_cast<int>(std::count(inlier.begin(), inlier.end(), 1));
  if (out.inliers < min_inliers)
    return false;
  Affine a_to_b(start.at<double>(0, 0), start.at<double>(0, 1), start.at<double>(0, 2), start.at<double>(1, 0),
                start.at<double>(1, 1), start.at<double>(1, 2));

  // Refine on the outlines: the places are a few and a table px apart at
  // best; the outlines hold hundreds of points. The pairs go both ways (each
  // of a's points to b's nearest, each of b's to a's nearest), so that
  // neither outline can shrink onto a part of the other.
  const std::vector<cv::Point2d> a_points = outlinePoints(a, identityAffine());
  const std::vector<cv::Point2d> b_points = outlinePoints(b, identityAffine());
  std::vector<std::pair<double, int>> a_to_b_nearest, b_to_a_nearest;
  const auto directedMedians = [&](const Affine& map, double& a_median, double& b_median) {
    const std::vector<cv::Point2d> mapped = outlinePoints(a, map);
    nearestPoints(mapped, b_points, a_to_b_nearest);
    nearestPoints(b_points, mapped, b_to_a_nearest);
    a_median = medianDistance(a_to_b_nearest);
    b_median = medianDistance(b_to_a_nearest);
  };
  double a_median = 0.0, b_median = 0.0;
  for (int pass = 0; pass < kRefinements; ++pass)
  {
    directedMedians(a_to_b, a_median, b_median);
    const std::vector<std::size_t> from_a = nearestShare(a_to_b_nearest), from_b = nearestShare(b_to_a_nearest);
    Eigen::MatrixXd from(2, from_a.size() + from_b.size()), to(2, from_a.size() + from_b.size());
    Eigen::Index column = 0;
    for (std::size_t i : from_a)
    {
      from.col(column) << a_points[i].x, a_points[i].y;
      to.col(column++) << b_points[a_to_b_nearest[i].second].x, b_points[a_to_b_nearest[i].second].y;
    }
    for (std::size_t j : from_b)
    {
      from.col(column) << a_points[b_to_a_nearest[j].second].x, a_points[b_to_a_nearest[j].second].y;
      to.col(column++) << b_points[j].x, b_points[j].y;
    }
    const Eigen::MatrixXd fitted = Eigen::umeyama(from, to, true);  // least-squares similarity, 3 x 3
    if (!fitted.allFinite() || fitted.topLeftCorner(2, 2).determinant() <= 0.0)
      break;
    a_to_b = toAffine(fitted);
  }
  directedMedians(a_to_b, a_median, b_median);
  out.outline_distance = std::max(a_median, b_median);
  out.a_to_b = a_to_b;
  return out.outline_distance <= max_outline_distance;
}
}  // namespace amcr
