#include "amcr/extraction/outline_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/outline_edges.h"
#include "amcr/extraction/outline_parts.h"

namespace amcr
{
namespace
{
// refineOnEdges: the search along the normals shrinks over the passes
// (passSearch) and points far beyond the typical one are clutter
// (clutterLimit), both in outline_edges.h. A pass fits only when this many outline points found their edge: at least
// kMinFitPoints and a kFitPointsDivisor-th of the outline.
constexpr std::size_t kMinFitPoints = 6;
constexpr std::size_t kFitPointsDivisor = 4;
}  // namespace

Affine refineOnEdges(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                     int iterations, double search, const std::vector<std::uint8_t>& skip)
{
  Affine current = table_to_image;
  if (iterations <= 0)
    return current;
  const int sign = dominantPolarity(scanner, mapOutline(prototype, current), search);
  for (int pass = 0; pass < iterations; ++pass)
  {
    // Coarse to fine: the search shrinks to a third over the passes.
    const double range = passSearch(search, pass, iterations);
    const std::vector<MappedPoint> mapped = mapOutline(prototype, current);
    std::vector<cv::Point2d> from, to;
    std::vector<double> residual;
    for (std::size_t i = 0; i < mapped.size(); ++i)
    {
      const MappedPoint& p = mapped[i];
      if (i < skip.size() && skip[i] != 0)
        continue;
      double offset = 0.0;
      if (!nearestEdge(scanner, p, range, sign, offset))
        continue;
      from.push_back(p.table);
      to.push_back(p.image + offset * p.normal);
      residual.push_back(std::abs(offset));
    }
    if (from.size() < std::max(kMinFitPoints, mapped.size() / kFitPointsDivisor))
      break;
    // Drop points whose edge is far beyond the typical one (clutter).
    const double limit = clutterLimit(residual);
    std::vector<cv::Point2d> kept_from, kept_to;
    for (std::size_t i = 0; i < from.size(); ++i)
      if (residual[i] <= limit)
      {
        kept_from.push_back(from[i]);
        kept_to.push_back(to[i]);
      }
    Affine next;
    if (!fitAffine(kept_from, kept_to, next))
      break;
    current = next;
  }
  return current;
}

double outlineSupport(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                      double tolerance, double part_shift)
{
  return verifyOutline(prototype, scanner, table_to_image, tolerance, part_shift, false).score;
}

OutlineVerification verifyOutline(const Prototype& prototype, const RadialScanner& scanner,
                                  const Affine& table_to_image, double tolerance, double part_shift,
                                  bool find_covered)
{
  std::vector<MappedPoint> mapped = mapOutline(prototype, table_to_image);
  fitPartsWithinShare(prototype, scanner, mapped, part_shift, tolerance);
  return verifyMappedOutline(scanner, mapped, prototype.outline().size(), tolerance,
                             find_covered && !prototype.isTemplate());
}

double verifyTolerance(double object_size, double tolerance, double relative)
{
  constexpr double kMinTolerance = 1.0;  // px
  if (!(relative > 0.0))
    return tolerance;
  return std::min(tolerance, std::max(kMinTolerance, relative * object_size));
}

double outlineSize(const std::vector<cv::Point2d>& outline)
{
  if (outline.size() < 2)
    return 0.0;
  const std::vector<cv::Point2f> points(outline.begin(), outline.end());
  const cv::RotatedRect box = cv::minAreaRect(points);
  return std::max(box.size.width, box.size.height);
}
}  // namespace amcr
