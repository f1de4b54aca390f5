// ObservationModel::measure in blocks of M-particles: a scalar pass gathers
// each one's table pixel, triangle ends and feature-ray ends (per-bin
// lookups, or with ray_correspondence affine and no refits the lookups of
// corrected_scan.h, in corrected_scan_lanes.cpp) into structure-of-arrays
// lanes, then plain float loops over the lanes (which the compiler
// vectorises) fit the triangle affine (paper 4.1) and sum eq. 6. Every lane
// does the same float operations in the same order as measureReference
// (observation_model.cpp, relational_update.h, affine.cpp), so the output
// is the same; a rejected triangle is masked, not branched around.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <string>

#include "amcr/base/errors.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/relational_update.h"
#include "amcr/memory/prototype_memory.h"
#include "observation_lanes.h"

namespace amcr
{
namespace measure_lanes
{
const HeadingRayBins& headingRayBins()
{
  static const HeadingRayBins bins;
  return bins;
}
}  // namespace measure_lanes

using namespace measure_lanes;  // the lanes and their steps (observation_lanes.h)

namespace
{
/// angleToBin (ray_directions.h) of `lanes` headings without the call to
/// lround: the same rounding half away from zero, from the exact fraction
/// x - trunc(x), in lanes. A heading beyond 1e9 bins (or not a number) gets
/// kNoRoundedBin, for the definition itself.
constexpr std::int32_t kNoRoundedBin = INT32_MIN;
void roundedBins(const float* theta, std::size_t lanes, std::int32_t rounded[kLanes])
{
  for (std::size_t l = 0; l < lanes; ++l)
  {
    const double x = static_cast<double>(theta[l]) / kBinAngle;
    const bool in_range = std::abs(x) < 1e9;
    const double x_in_range = in_range ? x : 0.0;
    const std::int32_t truncated = static_cast<std::int32_t>(x_in_range);
    const double fraction = x_in_range - static_cast<double>(truncated);
    const std::int32_t r = truncated + (fraction >= 0.5 ? 1 : 0) - (fraction <= -0.5 ? 1 : 0);
    rounded[l] = in_range ? r : kNoRoundedBin;
  }
}

inline int headingBin(std::int32_t rounded, float theta)
{
  if (rounded == kNoRoundedBin)
    return angleToBin(theta);
  const int bin = rounded % kDirectionBins;
  return bin < 0 ? bin + kDirectionBins : bin;
}

/// Asks for the cache lines of a pixel's table distances ahead of their use.
inline void prefetchDistances(const std::uint8_t* raw)
{
#if defined(__GNUC__)
  __builtin_prefetch(raw);
  __builtin_prefetch(raw + kDirectionBins - 1);
#else
  (void)raw;
#endif
}

/// tableRayEnd (relational_update.h) without the branch: the end and whether the ray met an edge.
inline std::int32_t tableEnd(const std::uint8_t* raw, float at_x, float at_y, const HeadingRayBins& bins, int bin,
                             float& x, float& y)
{
  const int d = raw[bin];
  x = at_x + d * bins.half_cos[bin];
  y = at_y + d * bins.half_sin[bin];
  return d != Prototype::kNoEdge;
}

/// Paper 4.1 in lanes: fitRelationalAffine (affineFromTriangles,
/// affineScaleAccepted, invertAffine of affine.cpp) on every lane, the
/// V-particle's triangle the destination of each.
void fitAffineLanes(const TableEndLanes& ends, const VRayEnds& v, float min_area, float max_scale, std::size_t lanes,
                    AffineLanes& out)
{
  const float d00 = v.triangle_x[1] - v.triangle_x[0], d01 = v.triangle_x[2] - v.triangle_x[0];
  const float d10 = v.triangle_y[1] - v.triangle_y[0], d11 = v.triangle_y[2] - v.triangle_y[0];
  const float dst_area2 = d00 * d11 - d01 * d10;
  const float area_limit = std::max(2.f * min_area, 1e-6f);
  const std::int32_t dst_accepted = std::abs(dst_area2) >= area_limit;
  const float min_scale = 1.f / max_scale;
  const float dst_x0 = v.triangle_x[0], dst_y0 = v.triangle_y[0];
  for (std::size_t l = 0; l < lanes; ++l)
  {
    const float sx0 = ends.triangle_x[0][l], sy0 = ends.triangle_y[0][l];
    const float s00 = ends.triangle_x[1][l] - sx0, s01 = ends.triangle_x[2][l] - sx0;
    const float s10 = ends.triangle_y[1][l] - sy0, s11 = ends.triangle_y[2][l] - sy0;
    const float src_area2 = s00 * s11 - s01 * s10;
    const std::int32_t area_accepted = std::abs(src_area2) >= area_limit;
    const float inv = 1.f / src_area2;
    const float i00 = s11 * inv, i01 = -s01 * inv, i10 = -s10 * inv, i11 = s00 * inv;
    const float b0 = d00 * i00 + d01 * i10;
    const float b1 = d00 * i01 + d01 * i11;
    const float b3 = d10 * i00 + d11 * i10;
    const float b4 = d10 * i01 + d11 * i11;
    const float b2 = dst_x0 - b0 * sx0 - b1 * sy0;
    const float b5 = dst_y0 - b3 * sx0 - b4 * sy0;
    // The singular values s1 >= s2 of B's linear part, closed form.
    const float det = b0 * b4 - b1 * b3;
    const float frob = b0 * b0 + b1 * b1 + b3 * b3 + b4 * b4;
    const float disc_squared = frob * frob - 4.f * det * det;
    const float disc = std::sqrt(0.f < disc_squared ? disc_squared : 0.f);
    const float s1 = std::sqrt(0.5f * (frob + disc));
    const float s2_squared = 0.5f * (frob - disc);
    const float s2 = std::sqrt(0.f < s2_squared ? s2_squared : 0.f);
    const std::int32_t scale_accepted = !(det <= 0.f || s1 > max_scale || s2 < min_scale);
    const std::int32_t invertible = det != 0.f && std::abs(det) <= FLT_MAX;
    const float inv_det = 1.f / det;
    const float a0 = b4 * inv_det, a1 = -b1 * inv_det, a3 = -b3 * inv_det, a4 = b0 * inv_det;
    out.b[0][l] = b0;
    out.b[1][l] = b1;
    out.b[2][l] = b2;
    out.b[3][l] = b3;
    out.b[4][l] = b4;
    out.b[5][l] = b5;
    out.a[0][l] = a0;
    out.a[1][l] = a1;
    out.a[2][l] = -(a0 * b2 + a1 * b5);
    out.a[3][l] = a3;
    out.a[4][l] = a4;
    out.a[5][l] = -(a3 * b2 + a4 * b5);
    out.accepted[l] = ends.triangle_found[l] & dst_accepted & area_accepted & scale_accepted & invertible;
  }
}
}  // namespace

void ObservationModel::measure(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m, std::size_t begin,
                               std::size_t end) const
{
  if (fit_.ray_correspondence == RayCorrespondence::kAffine && fit_.affine_refits > 0)
  {
    measureReference(memory, v, m, begin, end);
    return;
  }
  for (std::size_t block = begin; block < end; block += kLanes)
    measureBlock(memory, v, m, block, std::min(end, block + kLanes));
}

void ObservationModel::measureBlock(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m,
                                    std::size_t begin, std::size_t end) const
{
  const float log_invalid = static_cast<float>(log_invalid_);
  const float all_invalid = kFeatureRays * log_invalid;
  // The feature rays eq. 6 compares: those valid in v.
  int valid_rays[kFeatureRays];
  int valid_count = 0;
  for (int k = 0; k < kFeatureRays; ++k)
    if (v.feature_valid[k])
      valid_rays[valid_count++] = k;

  // Gather: each M-particle's table pixel and ray ends. An M-particle outside
  // its table ends the block; those before it are updated, then it throws.
  // The table rows are asked for first, all of the block's at once: the
  // lookups wait on memory, not on each other.
  const std::uint8_t* raw[kLanes];
  cv::Point at[kLanes];
  std::size_t lanes = 0;
  const Prototype* outside = nullptr;
  for (; begin + lanes < end; ++lanes)
  {
    const std::size_t i = begin + lanes;
    const Prototype& p = memory[m.prototype[i]];
    at[lanes] = nearestTablePixel(m.x[i], m.y[i]);
    if (!insideTable(p, at[lanes]))
    {
      outside = &p;
      break;
    }
    raw[lanes] = p.rawDistances(at[lanes].x, at[lanes].y);
    prefetchDistances(raw[lanes]);
  }
  const HeadingRayBins& bins = headingRayBins();
  std::int32_t rounded[kLanes];
  roundedBins(m.theta.data() + begin, lanes, rounded);
  TableEndLanes ends;
  const bool corrected = fit_.ray_correspondence == RayCorrespondence::kAffine;
  if (corrected && v.triangle_valid)
    correctedTriangleEnds(m, begin, lanes, raw, at, v, bins, ends);
  for (std::size_t l = 0; l < lanes && v.triangle_valid && !corrected; ++l)
  {
    const int bin = headingBin(rounded[l], m.theta[begin + l]);
    const float at_x = static_cast<float>(at[l].x), at_y = static_cast<float>(at[l].y);
    std::int32_t found = 1;
    for (int t = 0; t < kTriangleRays; ++t)
      found &= tableEnd(raw[l], at_x, at_y, bins, bins.triangle[bin][t], ends.triangle_x[t][l], ends.triangle_y[t][l]);
    ends.triangle_found[l] = found;
    for (int j = 0; j < valid_count; ++j)
      ends.ray_found[j][l] =
          tableEnd(raw[l], at_x, at_y, bins, bins.feature[bin][valid_rays[j]], ends.ray_x[j][l], ends.ray_y[j][l]);
  }

  if (!v.triangle_valid)
  {
    for (std::size_t i = begin; i < begin + lanes; ++i)
    {
      m.affine_valid[i] = kNoAffine;
      m.log_likelihood[i] = all_invalid;
    }
  }
  else
  {
    AffineLanes affine;
    fitAffineLanes(ends, v, fit_.min_triangle_area, fit_.max_affine_scale, lanes, affine);
    if (corrected)
      correctedFeatureEnds(affine, lanes, raw, at, v, valid_rays, valid_count, bins, ends);

    // Paper eq. 6: the sum over v's valid feature rays of log p(dw_j) (eq. 5,
    // tabulated as in logRayFromSquared) or log p_invalid, in ray order.
    // First, in lanes, the cell of cell_start_slope_ each ray's term comes
    // from (the last two: beyond the table, and no edge in it) and the
    // fraction into it; then the lookups and sums, one M-particle at a time.
    const float last_index = static_cast<float>(table_.size() - 1);
    const std::int32_t far_cell = static_cast<std::int32_t>(table_.size() - 1);
    const std::int32_t invalid_cell = far_cell + 1;
    float fraction[kFeatureRays][kLanes];
    std::int32_t cell[kFeatureRays][kLanes];
    for (int j = 0; j < valid_count; ++j)
    {
      const int k = valid_rays[j];
      const float image_x = v.feature_x[k], image_y = v.feature_y[k];
      for (std::size_t l = 0; l < lanes; ++l)
      {
        const float table_x = ends.ray_x[j][l], table_y = ends.ray_y[j][l];
        float dx, dy;
        if (fit_.deviation_space == DeviationSpace::kImage)
        {
          dx = affine.b[0][l] * table_x + affine.b[1][l] * table_y + affine.b[2][l] - image_x;
          dy = affine.b[3][l] * table_x + affine.b[4][l] * table_y + affine.b[5][l] - image_y;
        }
        else
        {
          dx = affine.a[0][l] * image_x + affine.a[1][l] * image_y + affine.a[2][l] - table_x;
          dy = affine.a[3][l] * image_x + affine.a[4][l] * image_y + affine.a[5][l] - table_y;
        }
        const float index = (dx * dx + dy * dy) * inv_step_;
        const bool in_table = index < last_index;  // false for not a number too
        const bool found = ends.ray_found[j][l] != 0;
        const float index_in_table = in_table ? index : 0.f;
        const std::int32_t truncated = static_cast<std::int32_t>(index_in_table);
        cell[j][l] = found ? (in_table ? truncated : far_cell) : invalid_cell;
        fraction[j][l] = found ? index_in_table - static_cast<float>(truncated) : 0.f;
      }
    }
    const float invalid_in_v = v.invalid_feature_rays * log_invalid;
    const float* start_slope = cell_start_slope_.data();
    float log_l[kLanes];
    for (std::size_t l = 0; l < lanes; ++l)
    {
      float sum = invalid_in_v;
      for (int j = 0; j < valid_count; ++j)
      {
        const float* cell_pair = start_slope + 2 * cell[j][l];
        sum += cell_pair[0] + fraction[j][l] * cell_pair[1];
      }
      log_l[l] = sum;
    }

    for (std::size_t l = 0; l < lanes; ++l)
    {
      const std::size_t i = begin + l;
      const bool accepted = affine.accepted[l] != 0;
      m.affine_valid[i] = accepted ? kFittedAffine : kNoAffine;
      m.log_likelihood[i] = accepted ? log_l[l] : all_invalid;
      if (accepted)
        for (int e = 0; e < 6; ++e)
          m.affine[e][i] = affine.a[e][l];
    }
  }
  if (outside)
    throw InputError("ObservationModel::measure: M-particle " + std::to_string(begin + lanes) +
                     " lies outside the table of '" + outside->label() + "'");
}
}  // namespace amcr
