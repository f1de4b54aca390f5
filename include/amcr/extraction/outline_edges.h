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

/// Per mapped point, 1 where it has an edge within `tolerance` px along its
/// normal with the polarity of the majority (dominantPolarity), else 0: the
/// points mappedOutlineSupport counts.
std::vector<std::uint8_t> pointsOnEdges(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        double tolerance);

}  // namespace amcr
