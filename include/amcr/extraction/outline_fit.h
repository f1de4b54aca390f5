// Verification and refinement of an object hypothesis against the image:
// the prototype's whole outline, mapped into the input, must lie on edges.
#pragma once

#include <vector>

#include "amcr/base/affine.h"
#include "amcr/extraction/outline_verification.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// Refines a table->image affine so that the prototype's outline lies on
/// image edges: each pass looks for the strongest edge within `search` px
/// along every outline point's normal and refits the affine to the points
/// found (least squares, residuals beyond 2.5x the median dropped).
/// Returns the input affine when too few edges are found. Outline points
/// set in `skip` (one flag per outline point, as OutlineVerification::covered)
/// take no part: an occluder's contour would pull the fit towards itself.
Affine refineOnEdges(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                     int iterations, double search, const std::vector<std::uint8_t>& skip = {});

/// Share, in [0, 1], of the outline points that have an image edge within
/// `tolerance` px along their normal, with the edge polarity the majority of
/// the outline shows. Points mapped outside the image count as missing.
/// With `part_shift` > 0 the inner parts of the outline (its holes') are
/// first fitted on their edges each on its own, by up to that share of the
/// object's size (outline_parts.h).
double outlineSupport(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                      double tolerance, double part_shift = 0.0);

/// outlineSupport with, when `find_covered` and the prototype is a
/// silhouette, the outline points that lie under something in front of the
/// object (covered_outline.h) left out: the score is then the share of the
/// visible outline on edges (outline_verification.h).
OutlineVerification verifyOutline(const Prototype& prototype, const RadialScanner& scanner,
                                  const Affine& table_to_image, double tolerance, double part_shift,
                                  bool find_covered);

/// The tolerance of the score for an object whose outline is `object_size`
/// px long (outlineSize): `relative` of that size, never above `tolerance`
/// and never below 1 px (edges are found to a pixel even out of focus);
/// `tolerance` itself when `relative` is 0. Likeness of shape is free of
/// scale: a blob that follows an outline within 2 px at 90 px long resembles
/// it no more closely than one within 6 px at 270 px.
double verifyTolerance(double object_size, double tolerance, double relative);

/// Size of an outline in the image: the longer side, in px, of the smallest
/// (rotated) rectangle around its points; 0 for fewer than 2 points.
double outlineSize(const std::vector<cv::Point2d>& outline);
}  // namespace amcr
