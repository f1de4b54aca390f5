// Outline points hidden behind something in front of the object. Of an
// outline point that finds no edge, the image either shows that the shape is
// not there (the object's inside or its surround goes on across the point)
// or shows another surface over it: an occluder, whose own contour crosses
// the outline. Only the second is covered; the decision then reads the
// visible outline (outline_verification.h).
#pragma once

#include <cstdint>
#include <vector>

#include "amcr/extraction/outline_edges.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// When an outline point with no edge counts as covered.
struct CoverRule
{
  /// A grey level within this share of the object's contrast (its inside
  /// against its surround) of another looks like it.
  double like = 0.3;
  /// Covered points come in runs of at least this share of the outline (an
  /// occluder's contour crosses the outline; it does not dot it); shorter
  /// runs are missing.
  double min_run = 0.03;
  /// Outline points on edges needed to read the object's inside and
  /// surround from, as a share of all.
  double min_on_edge = 0.25;
};

/// Per mapped outline point (`mapped`, of a silhouette: the outline's
/// normals point outwards), 1 where it lies under a surface in front of the
/// object, else 0. `on_edge` says per point whether it found its edge within
/// `tolerance` px. The object's inside and surround are read beside the
/// points on edges (the median grey just beyond the tolerance on either
/// side); a point without an edge is covered when the grey on both of its
/// sides is alike and unlike both of them, and a point on an edge when the
/// grey beyond it is unlike both (an occluder's contour running along the
/// outline), in a run of such points at least rule.min_run of the outline long. None is covered when the inside and the
/// surround differ by less than the scanner's edge threshold, or too few
/// points are on edges to read them.
std::vector<std::uint8_t> coveredPoints(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        const std::vector<std::uint8_t>& on_edge, double tolerance,
                                        const CoverRule& rule = CoverRule());
}  // namespace amcr
