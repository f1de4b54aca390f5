#include "amcr/extraction/outline_verification.h"

#include <algorithm>

#include "amcr/extraction/covered_outline.h"

namespace amcr
{
namespace
{
// Smallest share of the visible outline on edges with which an outline
// claims covered points. Clean occluded targets show 0.95-1; a fit on
// clutter that found "covered" stretches, 0.75-0.8.
constexpr double kCoveredMinScore = 0.9;
}  // namespace

OutlineVerification verifyMappedOutline(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        std::size_t outline_points, double tolerance, bool find_covered)
{
  OutlineVerification verification;
  if (mapped.empty() || outline_points == 0)
    return verification;
  const std::vector<std::uint8_t> on_edge = pointsOnEdges(scanner, mapped, tolerance);
  const int found = static_cast<int>(std::count(on_edge.begin(), on_edge.end(), 1));
  verification.score = static_cast<double>(found) / static_cast<double>(outline_points);
  if (!find_covered || mapped.size() != outline_points)
    return verification;
  std::vector<std::uint8_t> covered = coveredPoints(scanner, mapped, on_edge, tolerance);
  std::size_t visible = outline_points;
  int found_visible = found;
  for (std::size_t i = 0; i < mapped.size(); ++i)
    if (covered[i] != 0)
    {
      --visible;
      found_visible -= on_edge[i];  // an occluder's contour, not the object's outline
    }
  if (visible == outline_points || visible == 0)
    return verification;
  verification.covered_found = covered;
  // Only an outline whose visible part lies on its edges may claim the rest
  // covered: in clutter, a loose fit's missing points often lie over other
  // shapes, which look like occluders.
  const double visible_score = static_cast<double>(found_visible) / static_cast<double>(visible);
  if (visible_score < kCoveredMinScore)
    return verification;
  verification.covered = std::move(covered);
  verification.visible_share = static_cast<double>(visible) / static_cast<double>(outline_points);
  verification.score = visible_score;
  return verification;
}
}  // namespace amcr
