// Model selection between the affine and the homography fit of a recognized
// object: the affine stays the answer unless the outline
// demands a perspective view.
#pragma once

#include "amcr/base/affine.h"
#include "amcr/base/homography.h"
#include "amcr/extraction/outline_verification.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// The rule's figures (defaults: the stated rule, see choosePerspective).
struct PerspectiveRule
{
  double tolerance = 2.0;          ///< px: outline support tolerance, as in the object's score
  double part_shift = 0.0;         ///< the score's inner parts move on their own by this share of the size (outline_parts.h)
  double residual_cap = 3.0;       ///< px: outlineResidual's cap
  double min_affine_residual = 0.4;   ///< px: an affine this close to its edges is kept untried
  double residual_ratio = 0.7;     ///< the homography's residual must be at most this share of the affine's
  double min_residual_gain = 0.25; ///< px: and at least this much lower
  double max_residual = 1.2;       ///< px: and at most this: the homography must explain the outline
  double max_depth_ratio = 2.0;    ///< bound of the perspective terms: far / near depth over the outline's box
  double max_corner_shift = 0.2;   ///< the box's corners move at most this share of its mapped diagonal from the affine's
  double max_scale = 8.0;          ///< local scale bound (params.max_affine_scale)
  int pass_factor = 3;             ///< the homography gets this many times the affine's refinement passes
  bool find_covered = false;       ///< supports are of the visible outline (outline_fit.h: verifyOutline), as the score's
};

/// The outcome for one object (table px -> input px).
struct PerspectiveFit
{
  bool tried = false;           ///< the homography was fitted (the affine's residual left room to gain)
  bool used = false;            ///< the homography is the answer
  Homography homography;        ///< the fitted homography; the affine's lift when not tried
  Homography table_to_image;    ///< the answer: `homography` when used, else the affine's lift
  double affine_support = 0.0;      ///< outline support of the affine at rule.tolerance
  double homography_support = 0.0;  ///< the same of the homography (0 unless its residual and conditioning passed)
  /// The homography's verification (outline_verification.h; its score is
  /// homography_support), when its residual and conditioning passed.
  OutlineVerification verification;
  double affine_residual = 0.0;     ///< outlineResidual of the affine, px
  double homography_residual = 0.0; ///< the same of the homography (0 when not tried)
  double support = 0.0;         ///< outline support of the answer
};

/// Fits a homography from the refined affine (refineHomographyOnEdges with
/// `iterations` passes and `search` px) and uses it only when the outline
/// demands it, all of:
/// - the affine's residual is above rule.min_affine_residual (else it is not tried);
/// - the homography's residual is at most rule.residual_ratio of the affine's,
///   at least rule.min_residual_gain px below it, and at most rule.max_residual
///   (a homography bent onto clutter or onto another shape does not get there);
/// - its outline support is not below the affine's;
/// - it is well-conditioned over the outline's bounding box
///   (homographyWellConditioned with rule.max_scale, rule.max_depth_ratio) and
///   its corners stay within rule.max_corner_shift of the box's mapped
///   diagonal from where the affine puts them.
/// `affine_support` is outlineSupport of the affine at rule.tolerance (the
/// caller has it: the object's score).
PerspectiveFit choosePerspective(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                                 double affine_support, int iterations, double search,
                                 const PerspectiveRule& rule = PerspectiveRule());
}  // namespace amcr
