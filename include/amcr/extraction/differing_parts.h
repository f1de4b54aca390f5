// Look-alike shapes told apart on the parts where they differ: of two
// overlapping objects of alike prototypes (a bird with and without a crest,
// one bird in two poses), the whole outlines verify almost equally, since
// most of each lies on the other's edges; only the parts where the outlines
// are apart can tell which one the image shows.
#pragma once

#include <vector>

#include "amcr/extraction/outline_edges.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// The verification of two overlapping outlines on their differing parts.
struct DifferingParts
{
  int a_points = 0;         ///< points of outline a farther than `apart` px from outline b
  int b_points = 0;         ///< points of outline b farther than `apart` px from outline a
  double a_support = 0.0;   ///< share of a's differing points with an image edge within the tolerance
  double b_support = 0.0;   ///< the same for b
};

/// Compares the mapped outlines `a` and `b` (mapOutline of each object's
/// prototype and transform) on the parts where they are more than `apart`
/// px apart: each part's points are checked for an image edge within
/// `tolerance` px along their normal, as the verification checks the whole
/// outline (outline_fit.h), with the polarity the majority of each outline
/// shows.
DifferingParts compareDifferingParts(const RadialScanner& scanner, const std::vector<MappedPoint>& a,
                                     const std::vector<MappedPoint>& b, double tolerance, double apart);
}  // namespace amcr
