#include "amcr/extraction/outline_parts.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

namespace amcr
{
namespace
{
constexpr double kPartGap = 5.0;          // table px: 2.5 outline spacings (prototype.cpp) end a contour
constexpr std::size_t kMinPartPoints = 6; // a part needs this many points to be fitted on its own
constexpr double kMinPartFound = 0.5;     // and this share of them on edges
constexpr int kPartPasses = 3;

/// Moves the points [begin, end) of `out` by the translation and scale about
/// their centre that fit them best onto their edges.
void fitPart(const RadialScanner& scanner, std::vector<MappedPoint>& out, std::size_t begin, std::size_t end,
             int sign, double max_shift, double tolerance)
{
  const std::vector<MappedPoint> original(out.begin() + begin, out.begin() + end);
  cv::Point2d centre(0, 0);
  for (const MappedPoint& p : original)
    centre += p.image;
  centre *= 1.0 / static_cast<double>(original.size());
  double radius = 0.0;
  for (const MappedPoint& p : original)
    radius = std::max(radius, std::hypot(p.image.x - centre.x, p.image.y - centre.y));
  cv::Vec3d motion(0, 0, 0);  // tx, ty, scale - 1
  for (int pass = 0; pass < kPartPasses; ++pass)
  {
    const double search = tolerance + max_shift * (1.0 - static_cast<double>(pass) / (kPartPasses - 1));
    cv::Matx33d normal_matrix = cv::Matx33d::zeros();
    cv::Vec3d rhs(0, 0, 0);
    std::size_t found = 0;
    for (std::size_t i = 0; i < original.size(); ++i)
    {
      MappedPoint moved = original[i];
      const cv::Point2d r = original[i].image - centre;
      moved.image = original[i].image + cv::Point2d(motion[0], motion[1]) + motion[2] * r;
      double offset = 0.0;
      if (!nearestEdge(scanner, moved, search, sign, offset))
        continue;
      ++found;
      // The edge lies at the current motion plus `offset` along the normal:
      // n . t + s (n . r) = n . (current) + offset.
      const cv::Vec3d row(moved.normal.x, moved.normal.y, moved.normal.x * r.x + moved.normal.y * r.y);
      const double target = row.dot(motion) + offset;
      normal_matrix += row * row.t();
      rhs += target * row;
    }
    if (found < kMinPartPoints || found < kMinPartFound * original.size())
      return;
    cv::Vec3d next;
    if (!cv::solve(normal_matrix, rhs, next, cv::DECOMP_CHOLESKY))
      return;
    // No point moves by more than max_shift: the translation and the scale's
    // reach at the part's radius share it.
    const double reach = std::hypot(next[0], next[1]) + std::abs(next[2]) * radius;
    if (reach > max_shift)
      next *= max_shift / reach;
    motion = next;
  }
  for (std::size_t i = 0; i < original.size(); ++i)
  {
    const cv::Point2d r = original[i].image - centre;
    out[begin + i].image = original[i].image + cv::Point2d(motion[0], motion[1]) + motion[2] * r;
  }
}
}  // namespace

std::vector<std::pair<std::size_t, std::size_t>> outlineParts(const std::vector<MappedPoint>& mapped)
{
  std::vector<std::pair<std::size_t, std::size_t>> parts;
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= mapped.size(); ++i)
  {
    const bool ends = i == mapped.size() || std::hypot(mapped[i].table.x - mapped[i - 1].table.x,
                                                        mapped[i].table.y - mapped[i - 1].table.y) > kPartGap;
    if (ends && i > begin)
    {
      parts.emplace_back(begin, i);
      begin = i;
    }
  }
  return parts;
}

double partShiftLimit(const std::vector<MappedPoint>& mapped, double share)
{
  if (mapped.empty() || !(share > 0.0))
    return 0.0;
  double min_x = mapped[0].image.x, max_x = min_x, min_y = mapped[0].image.y, max_y = min_y;
  for (const MappedPoint& p : mapped)
  {
    min_x = std::min(min_x, p.image.x);
    max_x = std::max(max_x, p.image.x);
    min_y = std::min(min_y, p.image.y);
    max_y = std::max(max_y, p.image.y);
  }
  return share * std::max(max_x - min_x, max_y - min_y);
}

void fitPartsOnEdges(const RadialScanner& scanner, std::vector<MappedPoint>& mapped, double max_shift,
                     double tolerance)
{
  if (!(max_shift > 0.0) || mapped.empty())
    return;
  const auto parts = outlineParts(mapped);
  if (parts.size() < 2)
    return;
  const auto outer = std::max_element(parts.begin(), parts.end(), [](const auto& a, const auto& b) {
    return a.second - a.first < b.second - b.first;
  });
  const int sign = dominantPolarity(scanner, mapped, tolerance);
  for (auto part = parts.begin(); part != parts.end(); ++part)
    if (part != outer && part->second - part->first >= kMinPartPoints)
      fitPart(scanner, mapped, part->first, part->second, sign, max_shift, tolerance);
}
}  // namespace amcr
