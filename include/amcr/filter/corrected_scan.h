// Affine-corrected table lookups for oblique views. Under the affine A
// (input -> table) of a relational particle, the image ray of direction d
// from the V-particle corresponds to the table ray of direction L d from the
// M-particle (L: the linear part of A), not to the ray at the same angle from
// the M-particle's heading, as the paper's scheme assumes (paper 4.1; exact
// only for a similarity). At anisotropy 2 the two differ by up to 19 degrees.
// Here the table is read along L d, between its two nearest direction bins,
// and A is re-estimated from the triangle rays so corrected (a fixed point).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>

#include <opencv2/core.hpp>

#include "amcr/filter/relational_update.h"

namespace amcr
{
/// A direction in the table: unit vector and position in direction bins,
/// [0, kDirectionBins).
struct TableDirection
{
  float ux = 1.f;
  float uy = 0.f;
  float bin_position = 0.f;
};

/// The table direction that the row-major 2x2 linear map `l` takes image
/// direction (dx, dy) to. `l` must not be singular. Inline: it runs for every
/// ray of every relational particle.
inline TableDirection tableDirection(const float l[4], float dx, float dy)
{
  TableDirection dir;
  const float x = l[0] * dx + l[1] * dy;
  const float y = l[2] * dx + l[3] * dy;
  const float inverse_norm = 1.f / std::sqrt(x * x + y * y);
  dir.ux = x * inverse_norm;
  dir.uy = y * inverse_norm;
  // cv::fastAtan2 is within about 0.3 degrees, a sixteenth of a bin: it
  // only weighs the two bins the distance is read from.
  dir.bin_position = cv::fastAtan2(y, x) * (kDirectionBins / 360.f);
  if (!(dir.bin_position < kDirectionBins))
    dir.bin_position = 0.f;
  return dir;
}

namespace detail
{
// Two neighbouring bins hit the same straight edge when their distances
// differ by at most this much (raw units of Prototype::kDistanceUnit): at
// 5 degrees apart a straight edge changes the distance by r * tan(5 deg) /
// tan(incidence), well within 25% of r unless the ray grazes the edge.
constexpr int kSameEdgeAbsolute = 4;  // 2 px
constexpr int kSameEdgeRelativeQuarters = 1;  // 25% of the longer distance
}  // namespace detail

/// Where the table ray of direction `dir` from table pixel `at` ends, table
/// px, given the raw distances of `at` (Prototype::rawDistances). The
/// distance is interpolated between the two nearest bins when both meet an
/// edge at about the same distance (one straight edge); otherwise the nearest
/// bin's end point is taken as it is. False when the nearest bin meets no edge.
inline bool correctedRayEnd(const std::uint8_t* raw, const cv::Point& at, const TableDirection& dir, float& x,
                            float& y)
{
  const int below = static_cast<int>(dir.bin_position);
  const float above_share = dir.bin_position - static_cast<float>(below);
  const int b0 = below % kDirectionBins, b1 = (below + 1) % kDirectionBins;
  const int nearest = above_share < 0.5f ? b0 : b1;
  if (raw[nearest] == Prototype::kNoEdge)
    return false;
  const int r0 = raw[b0], r1 = raw[b1];
  const int larger = r0 > r1 ? r0 : r1;
  const int limit = detail::kSameEdgeRelativeQuarters * larger / 4;
  if (r0 != Prototype::kNoEdge && r1 != Prototype::kNoEdge &&
      std::abs(r0 - r1) <= (limit > detail::kSameEdgeAbsolute ? limit : detail::kSameEdgeAbsolute))
  {
    const float r = (static_cast<float>(r0) + above_share * static_cast<float>(r1 - r0)) * Prototype::kDistanceUnit;
    x = static_cast<float>(at.x) + r * dir.ux;
    y = static_cast<float>(at.y) + r * dir.uy;
    return true;
  }
  return tableRayEnd(raw, at, nearest, x, y);
}

/// The view shape (xx, xy, yy) of a frontal view: the identity.
constexpr float kFrontalShape[3] = {1.f, 0.f, 1.f};

/// The linear map an M-particle starts its lookup with: the view shape
/// `shape` (row-major 2x2, image -> table up to a rotation and a scale)
/// turned so that the image heading (hx, hy) maps onto the M-particle's
/// heading `theta` (rad). For the identity shape this is the paper's
/// correspondence: image angle phi -> theta + phi - heading.
void startingShape(const float shape[4], float theta, float hx, float hy, float l[4]);

/// The view shape of a relational affine `a` (row-major 2x3, image ->
/// table): the symmetric part P of A = R P, scaled to det 1, as (xx, xy,
/// yy). False (shape untouched) when A is singular, mirrored or not finite.
bool viewShape(const float a[6], float shape[3]);

/// Anisotropy of a view shape (xx, xy, yy): the ratio of its singular values, >= 1.
float shapeAnisotropy(const float shape[3]);

/// The view shape (xx, xy, yy) of det 1 that stretches by sqrt(anisotropy)
/// along direction `axis` (rad) and squashes by as much across it.
void obliqueShape(float anisotropy, float axis, float shape[3]);

/// Diffuses a view shape: P <- E P E with E = I + (e1, e2; e2, -e1) / 2,
/// then scaled back to det 1 (e1, e2 ~ N(0, sigma^2), drawn by the caller).
void diffuseShape(float e1, float e2, float shape[3]);

/// The relational affine of paper 4.1 with affine-corrected lookups: looks
/// the table triangle up along the directions `l` takes v's triangle rays to,
/// fits B (and A = B^-1), then re-estimates `refits` times from the lookups
/// along the fitted A. False when the first fit fails (triangle ray without
/// an edge, degenerate triangle, scale out of range, mirror: as
/// fitRelationalAffine); a later fit that fails keeps the last good one.
bool fitCorrectedAffine(const std::uint8_t* raw, const cv::Point& at, const float l[4], const VRayEnds& v,
                        int refits, float min_area, float max_scale, RelationalAffine& out);

/// The linear part of A (image -> table), row-major 2x2.
inline void linearPart(const RelationalAffine& affine, float l[4])
{
  l[0] = affine.image_to_table[0];
  l[1] = affine.image_to_table[1];
  l[2] = affine.image_to_table[3];
  l[3] = affine.image_to_table[4];
}
}  // namespace amcr
