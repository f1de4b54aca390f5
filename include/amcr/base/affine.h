// 2D affine transforms and the triangle affine estimator E_a (paper 4.1):
// the unique affine map taking triangle (a, b, c) onto (a', b', c').
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace amcr
{
/// x' = m00 x + m01 y + m02, y' = m10 x + m11 y + m12 (pixel-centre convention).
using Affine = cv::Matx23d;

/// Solves A a = a', A b = b', A c = c'. Returns false (and leaves `out`
/// untouched) when the source or destination triangle has an area below
/// `min_area` (px^2 in its own image): collinear or coincident points give no A.
bool affineFromTriangles(const cv::Point2d src[3], const cv::Point2d dst[3], double min_area, Affine& out);

/// Float version for the hot loop; the same contract. `out` is row-major 2x3
/// (m00 m01 m02 m10 m11 m12).
bool affineFromTriangles(const float src_x[3], const float src_y[3], const float dst_x[3], const float dst_y[3],
                         float min_src_area, float min_dst_area, float out[6]);

/// Float, for the hot loop: whether the linear part of `a` (row-major 2x3)
/// could be a physical print's: not mirrored (det > 0) and both singular
/// values within [1 / max_scale, max_scale].
bool affineScaleAccepted(const float a[6], float max_scale);

/// Float inverse for the hot loop (row-major 2x3); returns false, leaving
/// `inverse` untouched, when `a` is singular or not finite.
bool invertAffine(const float a[6], float inverse[6]);

/// Inverse of an affine map; returns false when it is singular.
bool invertAffine(const Affine& a, Affine& inverse);

/// Composition: (first then second)(x) = second(first(x)).
Affine composeAffine(const Affine& first, const Affine& second);

inline cv::Point2d applyAffine(const Affine& a, const cv::Point2d& p)
{
  return {a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2), a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2)};
}

/// The identity map.
inline Affine identityAffine() { return Affine(1, 0, 0, 0, 1, 0); }

/// Largest and smallest singular value of the linear part.
void affineScales(const Affine& a, double& smallest, double& largest);

/// Least-squares affine taking `from` onto `to` (the same number of points,
/// at least 3); false when the points do not fix an affine (collinear).
bool fitAffine(const std::vector<cv::Point2d>& from, const std::vector<cv::Point2d>& to, Affine& out);
}  // namespace amcr
