// Verification against simpler explanations: a report must explain the
// image's edges better than the generic shapes that could explain them as
// well: an ellipse, the prototype's convex hull, its rectangle, a pair of
// lines. Most of an apple's outline lies on the edge of any round blob; only
// its stem tells the apple from a disc. The parts of the prototype's outline
// that lie apart from such a rival are what distinguishes the prototype from
// it, and they must be on the image's edges for a report, whatever the score
// of the whole outline (the look-alike places of differing_parts.h, against
// shapes that are not in memory).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/homography.h"
#include "amcr/extraction/outline_edges.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// A generic shape fitted to a prototype's outer outline, table px.
struct GenericRival
{
  enum class Kind
  {
    kEllipse,     ///< the ellipse most of the outline follows (robust fit)
    kConvexHull,  ///< the outline's convex hull
    kRectangle,   ///< the smallest rectangle around the outline
    kLinePair,    ///< the rectangle's two longer sides, as lines without end
  };
  Kind kind = Kind::kEllipse;
  /// A closed polygon; for kLinePair two points of each line (4 points).
  std::vector<cv::Point2d> points;
};

/// "ellipse", "convex hull", "rectangle", "pair of lines".
const char* rivalName(GenericRival::Kind kind);

/// The generic rivals of a prototype, fitted to the outer contour of its
/// mask (the holes' outlines are parts that tell it from all of them).
/// Empty when the mask holds no contour of at least 5 points.
std::vector<GenericRival> genericRivals(const Prototype& prototype);

/// The verification of an outline against its generic rivals.
struct RivalVerdict
{
  /// Share of the distinguishing points (those farther than `apart` from the
  /// rival) that have an image edge within the tolerance, for the rival whose
  /// share is lowest; 1 when no rival has enough distinguishing points.
  double support = 1.0;
  int points = 0;                                      ///< distinguishing points of that rival
  GenericRival::Kind rival = GenericRival::Kind::kEllipse;  ///< that rival
  bool tested = false;                                 ///< some rival had enough distinguishing points
  /// A rival's distinguishing points are mostly covered (fewer than half
  /// of them, or fewer than `min_points`, visible): what shows of the object
  /// does not tell it from that rival.
  bool hidden = false;
};

/// Checks the prototype's outline, mapped into the image by `table_to_image`
/// (`mapped`: mapOutline of the same transform), against each of `rivals`
/// mapped likewise: the outline points farther than `apart` px from the
/// rival's outline (or from both of its lines) distinguish the prototype
/// from it; a rival with fewer than `min_points` of them is not tested (the
/// prototype is that generic shape, as far as the image can tell). Each
/// distinguishing point is checked for an edge within `tolerance` px along
/// its normal, with the polarity of the outline's majority, as the score
/// checks the whole outline (outline_fit.h). With `covered` (per mapped
/// point, 1 where it is covered: covered_outline.h), only the visible
/// distinguishing points count towards the support.
RivalVerdict verifyAgainstRivals(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                 const std::vector<GenericRival>& rivals, const Homography& table_to_image,
                                 double tolerance, double apart, int min_points,
                                 const std::vector<std::uint8_t>& covered = {});
}  // namespace amcr
