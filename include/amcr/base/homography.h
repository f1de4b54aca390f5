// 2D homographies (8 degrees of freedom): the perspective view of a planar
// prototype, of which the affine (affine.h) is the first-order answer.
#pragma once

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"

namespace amcr
{
/// x' = (h00 x + h01 y + h02) / w, y' = (h10 x + h11 y + h12) / w,
/// w = h20 x + h21 y + h22 (pixel-centre convention). Kept with h22 = 1.
using Homography = cv::Matx33d;

/// The affine as a homography: its rows, then (0, 0, 1).
Homography liftAffine(const Affine& a);

/// Maps a point; (NaN, NaN) where w is not positive (the point would lie
/// behind the camera, or on the horizon).
cv::Point2d applyHomography(const Homography& h, const cv::Point2d& p);

/// Composition: (first then second)(x) = second(first(x)), scaled to h22 = 1
/// (left unscaled when the product's h22 is zero or not finite).
Homography composeHomography(const Homography& first, const Homography& second);

/// `h` scaled to h22 = 1; false (leaving `out` untouched) when h22 is zero
/// or an entry is not finite.
bool normalizeHomography(const Homography& h, Homography& out);

/// The Jacobian of `h` at `p`: the affine that best approximates it there.
/// False when w(p) is not positive.
bool homographyJacobian(const Homography& h, const cv::Point2d& p, cv::Matx22d& jacobian);
}  // namespace amcr
