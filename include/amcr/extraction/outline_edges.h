// The edge search along an outline's normals that the affine and the
// homography fits on the image share (outline_fit.h, homography_fit.h): an
// outline point mapped into the input, its normal there, and the nearest
// edge of a given polarity along that normal.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// An outline point mapped into the image with its image-space unit normal.
struct MappedPoint
{
  cv::Point2d table;   ///< the outline point, table px
  cv::Point2d image;   ///< where the fitted transform puts it, input px
  cv::Point2d normal;  ///< the outline's outward unit normal there, input px
  int polarity = 0;    ///< the prototype's polarity() : +1 = only edges rising along the normal count; 0 = either
};

/// The prototype's outline mapped by a table -> image affine (normals by the
/// inverse transpose of its linear part); empty when the affine is singular.
std::vector<MappedPoint> mapOutline(const Prototype& prototype, const Affine& table_to_image);

/// The nearest edge of polarity `sign` (+1: grey rises outwards, -1: falls)
/// within `search` px of `p` along its normal: the local maximum of the
/// signed step I(t + 1) - I(t - 1), sampled every 0.5 px, closest to the point
/// (the "moving edges" search of model-based trackers). `offset` is in px
/// along the normal, a multiple of 0.5. False when there is none.
bool nearestEdge(const RadialScanner& scanner, const MappedPoint& p, double search, int sign, double& offset);

/// nearestEdge with the offset refined to a fraction of a sample by a
/// parabola through the step and its two neighbours.
bool nearestEdgeSubpixel(const RadialScanner& scanner, const MappedPoint& p, double search, int sign, double& offset);

/// The polarity most outline points show: +1 when the grey level rises
/// outwards (a dark print on light paper), -1 otherwise; a sample of the
/// points is enough to tell. A prototype with a polarity of its own
/// (Prototype::polarity(), carried by its mapped points) gives that one.
int dominantPolarity(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped, double search);

/// The search along the normals in pass `pass` of `passes` of an outline
/// fit (affine or homography), px: from `search` it shrinks to a third over
/// the passes (coarse to fine), never below 1.5 px.
double passSearch(double search, int pass, int passes);

/// The largest distance (px) from its edge at which an outline point still
/// takes part in a fit, given the distances `residual` of all of them: 2.5
/// times their median, at least 1 px; the points beyond are clutter.
/// `residual` must not be empty.
double clutterLimit(std::vector<double> residual);

/// Share, in [0, 1], of the `outline_points` outline points (mapped into the
/// image: `mapped`, those outside left out) that have an edge within
/// `tolerance` px along their normal, with the polarity of the majority.
double mappedOutlineSupport(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                            std::size_t outline_points, double tolerance);

/// An outline verified on the image's edges, with the points that lie under
/// something in front of the object told from those that are missing.
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

/// mappedOutlineSupport with, when `find_covered`, the covered points
/// (covered_outline.h) left out of the score: it is then the share of the
/// visible outline on edges. Covered points are claimed only when that share
/// is at least 0.9 (a loose fit on clutter finds "covered" stretches over
/// other shapes) and `mapped` is the whole outline of a silhouette (one
/// mapped point per outline point); otherwise none is covered and the score
/// is mappedOutlineSupport's.
OutlineVerification verifyMappedOutline(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        std::size_t outline_points, double tolerance, bool find_covered);
}  // namespace amcr
