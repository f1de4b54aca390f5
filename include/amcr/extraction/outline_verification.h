// The verification of a mapped outline on the image's edges with the points
// under something in front of the object told from the missing ones
// (covered_outline.h): the score of the visible outline and how much of it
// is visible.
#pragma once

#include <cstdint>
#include <vector>

#include "amcr/extraction/outline_edges.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// An outline verified on the image's edges.
struct OutlineVerification
{
  /// Share, in [0, 1], of the visible outline points (those not covered)
  /// with an edge within the tolerance; 0 when none is visible.
  double score = 0.0;
  /// Share, in [0, 1], of the outline points not covered.
  double visible_share = 1.0;
  /// Per mapped point, 1 where it is covered (covered_outline.h); empty when
  /// none is claimed.
  std::vector<std::uint8_t> covered;
  /// The points found covered whether claimed or not (a fit pulled onto an
  /// occluder's contour claims none yet: outline_fit.h refits without them);
  /// empty when none was found or none was looked for.
  std::vector<std::uint8_t> covered_found;
};

/// mappedOutlineSupport (outline_edges.h) with, when `find_covered`, the
/// covered points (covered_outline.h) left out of the score: it is then the
/// share of the visible outline on edges. Covered points are claimed only
/// when that share is at least 0.9 (a loose fit on clutter finds "covered"
/// stretches over other shapes) and `mapped` is the whole outline of a
/// silhouette (one mapped point per outline point); otherwise none is
/// covered and the score is mappedOutlineSupport's.
OutlineVerification verifyMappedOutline(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        std::size_t outline_points, double tolerance, bool find_covered);
}  // namespace amcr
