// The homography fit of a recognized object on the image:
// the same edge search along the outline's normals as the affine fit
// (outline_fit.h), with a homography (8 degrees of freedom) fitted robustly
// to the edges found, so that a planar shape seen in perspective lies on
// its edges all round. Whether it replaces the affine is decided in
// perspective_choice.h.
#pragma once

#include <string>
#include <vector>

#include "amcr/base/homography.h"
#include "amcr/extraction/outline_edges.h"
#include "amcr/extraction/outline_verification.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// The prototype's outline mapped by a table -> image homography, normals by
/// the inverse transpose of its Jacobian at each point. Points where the
/// homography is not defined (w <= 0) or singular are left out.
std::vector<MappedPoint> mapOutline(const Prototype& prototype, const Homography& table_to_image);

/// The corners of the bounding box of the prototype's outline, table px,
/// in order around it; empty for an empty outline.
std::vector<cv::Point2d> outlineBox(const Prototype& prototype);

/// Refines a table -> image homography so that the prototype's outline lies
/// on image edges: each pass looks for the nearest edge (of the outline's
/// majority polarity, to a fraction of a pixel) within a search along every
/// outline point's normal that shrinks from `search` to a third of it (at
/// least 1.5 px) over the passes, fits a homography to the edges found by
/// least squares (cv::findHomography, method 0: linear, then
/// Levenberg-Marquardt), and refits it without the points it maps beyond
/// 2.5x the median distance (at least 1 px) from their edge (clutter).
/// Stops early once a pass (from the fourth on) moves no corner of the
/// outline's box by 0.05 px, and, keeping the last good homography, when too
/// few edges are found (8, and a quarter of the outline) or a fit fails.
Homography refineHomographyOnEdges(const Prototype& prototype, const RadialScanner& scanner,
                                   const Homography& table_to_image, int iterations, double search);

/// outlineSupport (outline_fit.h) of the outline mapped by a homography.
double outlineSupport(const Prototype& prototype, const RadialScanner& scanner, const Homography& table_to_image,
                      double tolerance, double part_shift = 0.0);

/// verifyOutline (outline_fit.h) under a homography.
OutlineVerification verifyOutline(const Prototype& prototype, const RadialScanner& scanner,
                                  const Homography& table_to_image, double tolerance, double part_shift,
                                  bool find_covered);

/// How far the mapped outline lies from its edges: the mean over all outline
/// points of the distance, px, to the nearest edge of the majority polarity
/// along the normal (to a fraction of a pixel), each capped at `cap`; a point
/// without an edge within `cap` (or mapped outside the image) counts as `cap`.
double outlineResidual(const Prototype& prototype, const RadialScanner& scanner, const Homography& table_to_image,
                       double cap);

/// Whether a table -> image homography is a plausible view of the region
/// (a convex polygon, table px, e.g. the outline's bounding box): defined
/// (w > 0) at every vertex, depth ratio max w / min w at most
/// `max_depth_ratio` (bounded perspective terms), not mirrored and not
/// degenerate (the Jacobian's singular values within [1 / max_scale,
/// max_scale] at every vertex, determinant > 0), and the mapped region still
/// convex with the same orientation. `why` (when given) says what failed.
bool homographyWellConditioned(const Homography& table_to_image, const std::vector<cv::Point2d>& region,
                               double max_scale, double max_depth_ratio, std::string* why = nullptr);
}  // namespace amcr
