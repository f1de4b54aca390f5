// The corrected lookups of ObservationModel::measure's lanes
// (ray_correspondence affine, no refits): tableDirection and
// correctedRayEnd of corrected_scan.h for a block of M-particles, in float
// loops over the lanes but for the arctangent and the table reads, with the
// same float operations in the same order as there, so the output is the same.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "amcr/filter/corrected_scan.h"
#include "observation_lanes.h"

namespace amcr
{
namespace measure_lanes
{
namespace
{
/// tableDirection (corrected_scan.h) of `lanes` M-particles in lanes: the
/// direction the linear map l (row-major 2x2, lane-wise) takes image
/// direction (dx, dy) to, unnormalised (x, y) and unit (ux, uy).
struct DirectionLanes
{
  float x[kLanes], y[kLanes], ux[kLanes], uy[kLanes];
};

void directionLanes(const float (&l)[4][kLanes], float dx, float dy, std::size_t lanes, DirectionLanes& out)
{
  for (std::size_t i = 0; i < lanes; ++i)
  {
    const float x = l[0][i] * dx + l[1][i] * dy;
    const float y = l[2][i] * dx + l[3][i] * dy;
    const float inverse_norm = 1.f / std::sqrt(x * x + y * y);
    out.x[i] = x;
    out.y[i] = y;
    out.ux[i] = x * inverse_norm;
    out.uy[i] = y * inverse_norm;
  }
}

/// mask ? a : b for a mask of all ones or all zeros, on the bits: the same
/// value, as a select the vectoriser takes (GCC 12 does not take the float one
/// on an integer condition).
inline float selectBits(std::int32_t mask, float a, float b)
{
  std::int32_t bits_a, bits_b;
  std::memcpy(&bits_a, &a, sizeof a);
  std::memcpy(&bits_b, &b, sizeof b);
  const std::int32_t bits = (bits_a & mask) | (bits_b & ~mask);
  float out;
  std::memcpy(&out, &bits, sizeof out);
  return out;
}

/// The rest of tableDirection (the position in direction bins, by
/// cv::fastAtan2 as there) and correctedRayEnd (corrected_scan.h) for the
/// lanes whose `active` is set, in lanes but for the arctangent and the table
/// reads; `found` is 0 for the others.
void correctedEnds(const DirectionLanes& d, std::size_t lanes, const std::int32_t* active,
                   const std::uint8_t* const raw[], const cv::Point at[], const HeadingRayBins& bins, float* x,
                   float* y, std::int32_t* found)
{
  float position[kLanes];
  for (std::size_t i = 0; i < lanes; ++i)
  {
    const float p = active[i] ? cv::fastAtan2(d.y[i], d.x[i]) * (kDirectionBins / 360.f) : 0.f;
    position[i] = p < kDirectionBins ? p : 0.f;  // not a number too
  }
  float share[kLanes];
  std::int32_t bin0[kLanes], bin1[kLanes], nearest[kLanes];
  for (std::size_t i = 0; i < lanes; ++i)
  {
    const std::int32_t below = static_cast<std::int32_t>(position[i]);  // [0, kDirectionBins)
    share[i] = position[i] - static_cast<float>(below);
    bin0[i] = below;
    bin1[i] = below + 1 == kDirectionBins ? 0 : below + 1;
    nearest[i] = share[i] < 0.5f ? bin0[i] : bin1[i];
  }
  std::int32_t r0[kLanes], r1[kLanes], rn[kLanes];
  float step_x[kLanes], step_y[kLanes], at_x[kLanes], at_y[kLanes];
  for (std::size_t i = 0; i < lanes; ++i)  // the table reads, scalar
  {
    r0[i] = raw[i][bin0[i]];
    r1[i] = raw[i][bin1[i]];
    rn[i] = raw[i][nearest[i]];
    step_x[i] = bins.half_cos[nearest[i]];
    step_y[i] = bins.half_sin[nearest[i]];
    at_x[i] = static_cast<float>(at[i].x);
    at_y[i] = static_cast<float>(at[i].y);
  }
  for (std::size_t i = 0; i < lanes; ++i)
  {
    const std::int32_t larger = r0[i] > r1[i] ? r0[i] : r1[i];
    const std::int32_t quarter = detail::kSameEdgeRelativeQuarters * larger / 4;
    const std::int32_t limit = quarter > detail::kSameEdgeAbsolute ? quarter : detail::kSameEdgeAbsolute;
    const std::int32_t gap = std::abs(r0[i] - r1[i]);
    const std::int32_t one_edge =
        -((r0[i] != Prototype::kNoEdge) & (r1[i] != Prototype::kNoEdge) & (gap <= limit));  // all ones or zeros
    // One straight edge: the distance interpolated along the direction; else the nearest bin's end (tableRayEnd).
    const float r =
        (static_cast<float>(r0[i]) + share[i] * static_cast<float>(r1[i] - r0[i])) * Prototype::kDistanceUnit;
    const float nearest_x = at_x[i] + static_cast<float>(rn[i]) * step_x[i];
    const float nearest_y = at_y[i] + static_cast<float>(rn[i]) * step_y[i];
    const float along_x = at_x[i] + r * d.ux[i];
    const float along_y = at_y[i] + r * d.uy[i];
    x[i] = selectBits(one_edge, along_x, nearest_x);
    y[i] = selectBits(one_edge, along_y, nearest_y);
    found[i] = (active[i] != 0) & (rn[i] != Prototype::kNoEdge);
  }
}
}  // namespace

/// ray_correspondence affine, no refits: the triangle ends of each M-particle
/// read along its view shape turned onto its heading (startingShape), as
/// fitCorrectedAffine's first pass reads them.
void correctedTriangleEnds(const MParticleSet& m, std::size_t begin, std::size_t lanes,
                           const std::uint8_t* const raw[], const cv::Point at[], const VRayEnds& v,
                           const HeadingRayBins& bins, TableEndLanes& ends)
{
  float l[4][kLanes];
  for (std::size_t i = 0; i < lanes; ++i)
  {
    const std::size_t p = begin + i;
    const float assumed[4] = {m.shape[0][p], m.shape[1][p], m.shape[1][p], m.shape[2][p]};
    float shape[4];
    startingShape(assumed, m.theta[p], v.feature_dx[0], v.feature_dy[0], shape);
    for (int e = 0; e < 4; ++e)
      l[e][i] = shape[e];
  }
  for (std::size_t i = 0; i < lanes; ++i)
    ends.triangle_found[i] = 1;
  DirectionLanes d;
  for (int t = 0; t < kTriangleRays; ++t)
  {
    directionLanes(l, v.triangle_dx[t], v.triangle_dy[t], lanes, d);
    std::int32_t active[kLanes];
    std::copy(ends.triangle_found, ends.triangle_found + lanes, active);
    correctedEnds(d, lanes, active, raw, at, bins, ends.triangle_x[t], ends.triangle_y[t], ends.triangle_found);
  }
}

/// ray_correspondence affine: the ends of v's valid feature rays (valid_rays)
/// read along the fitted A's linear part, for the accepted lanes
/// (correctedLogLikelihood); the others meet no edge.
void correctedFeatureEnds(const AffineLanes& affine, std::size_t lanes, const std::uint8_t* const raw[],
                          const cv::Point at[], const VRayEnds& v, const int* valid_rays, int valid_count,
                          const HeadingRayBins& bins, TableEndLanes& ends)
{
  float l[4][kLanes];
  for (std::size_t i = 0; i < lanes; ++i)
  {
    l[0][i] = affine.a[0][i];
    l[1][i] = affine.a[1][i];
    l[2][i] = affine.a[3][i];
    l[3][i] = affine.a[4][i];
  }
  DirectionLanes d;
  for (int j = 0; j < valid_count; ++j)
  {
    directionLanes(l, v.feature_dx[valid_rays[j]], v.feature_dy[valid_rays[j]], lanes, d);
    correctedEnds(d, lanes, affine.accepted, raw, at, bins, ends.ray_x[j], ends.ray_y[j], ends.ray_found[j]);
  }
}
}  // namespace measure_lanes
}  // namespace amcr
