#include "amcr/extraction/perspective_choice.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "amcr/extraction/homography_fit.h"

namespace amcr
{
namespace
{
/// Whether the homography keeps the box's corners near the affine's.
bool nearAffine(const Homography& h, const Affine& a, const std::vector<cv::Point2d>& box, double max_shift)
{
  const cv::Point2d diagonal = applyAffine(a, box[2]) - applyAffine(a, box[0]);
  const double limit = max_shift * std::max(std::hypot(diagonal.x, diagonal.y),
                                            std::hypot((applyAffine(a, box[3]) - applyAffine(a, box[1])).x,
                                                       (applyAffine(a, box[3]) - applyAffine(a, box[1])).y));
  for (const cv::Point2d& c : box)
  {
    const cv::Point2d d = applyHomography(h, c) - applyAffine(a, c);
    if (!(std::hypot(d.x, d.y) <= limit))
      return false;
  }
  return true;
}
}  // namespace

PerspectiveFit choosePerspective(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                                 double affine_support, int iterations, double search, const PerspectiveRule& rule)
{
  PerspectiveFit fit;
  const Homography lifted = liftAffine(table_to_image);
  fit.homography = lifted;
  fit.table_to_image = lifted;
  fit.affine_support = affine_support;
  fit.support = affine_support;
  if (prototype.outline().size() < 4)
    return fit;
  fit.affine_residual = outlineResidual(prototype, scanner, lifted, rule.residual_cap);
  if (fit.affine_residual <= rule.min_affine_residual)
    return fit;  // the affine already lies on the edges: nothing to gain
  fit.tried = true;
  fit.homography = refineHomographyOnEdges(prototype, scanner, lifted, rule.pass_factor * iterations, search);
  fit.homography_residual = outlineResidual(prototype, scanner, fit.homography, rule.residual_cap);
  if (fit.homography_residual > rule.residual_ratio * fit.affine_residual ||
      fit.homography_residual > fit.affine_residual - rule.min_residual_gain ||
      fit.homography_residual > rule.max_residual)
    return fit;
  const std::vector<cv::Point2d> box = outlineBox(prototype);
  if (!homographyWellConditioned(fit.homography, box, rule.max_scale, rule.max_depth_ratio) ||
      !nearAffine(fit.homography, table_to_image, box, rule.max_corner_shift))
    return fit;
  fit.verification = verifyOutline(prototype, scanner, fit.homography, rule.tolerance, rule.part_shift, rule.find_covered);
  fit.homography_support = fit.verification.score;
  if (fit.homography_support < affine_support)
    return fit;
  fit.used = true;
  fit.table_to_image = fit.homography;
  fit.support = fit.homography_support;
  return fit;
}
}  // namespace amcr
