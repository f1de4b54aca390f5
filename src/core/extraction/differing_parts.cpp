#include "amcr/extraction/differing_parts.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace amcr
{
namespace
{
std::vector<cv::Point2f> polygon(const std::vector<MappedPoint>& outline)
{
  std::vector<cv::Point2f> points;
  points.reserve(outline.size());
  for (const MappedPoint& p : outline)
    points.emplace_back(static_cast<float>(p.image.x), static_cast<float>(p.image.y));
  return points;
}

/// How many of `outline`'s points lie farther than `apart` px from `other`,
/// and how many of those find an edge.
void checkPart(const RadialScanner& scanner, const std::vector<MappedPoint>& outline,
               const std::vector<cv::Point2f>& other, double tolerance, double apart, int& points, double& support)
{
  points = 0;
  support = 0.0;
  if (outline.empty() || other.size() < 3)
    return;
  const int sign = dominantPolarity(scanner, outline, tolerance);
  int found = 0;
  for (const MappedPoint& p : outline)
  {
    const cv::Point2f at(static_cast<float>(p.image.x), static_cast<float>(p.image.y));
    if (!(std::abs(cv::pointPolygonTest(other, at, true)) > apart))
      continue;
    ++points;
    double offset = 0.0;
    found += nearestEdge(scanner, p, tolerance, sign, offset) ? 1 : 0;
  }
  support = points > 0 ? static_cast<double>(found) / points : 0.0;
}
}  // namespace

DifferingParts compareDifferingParts(const RadialScanner& scanner, const std::vector<MappedPoint>& a,
                                     const std::vector<MappedPoint>& b, double tolerance, double apart)
{
  DifferingParts out;
  checkPart(scanner, a, polygon(b), tolerance, apart, out.a_points, out.a_support);
  checkPart(scanner, b, polygon(a), tolerance, apart, out.b_points, out.b_support);
  return out;
}
}  // namespace amcr
