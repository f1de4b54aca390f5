// The measurement of one V-particle and the update of its relational
// particles (v, m): the triangle affine of paper 4.1 and the likelihood of
// eqs. 5-6.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "amcr/affine.h"
#include "amcr/particle_filter.h"
#include "amcr/ray_directions.h"

namespace amcr
{
namespace
{
/// cos and sin of every direction bin.
struct BinDirections
{
  float cos[kDirectionBins];
  float sin[kDirectionBins];
  BinDirections()
  {
    for (int b = 0; b < kDirectionBins; ++b)
    {
      cos[b] = static_cast<float>(std::cos(binToAngle(b)));
      sin[b] = static_cast<float>(std::sin(binToAngle(b)));
    }
  }
};
const BinDirections& binDirections()
{
  static const BinDirections directions;
  return directions;
}

/// Offset that makes the truncation of a table coordinate round it to the
/// nearest pixel, also for small negative values (-0.4 goes to 0, -0.6 to -1).
constexpr float kRoundingOffset = 1024.f;

/// The nearest table pixel of a table coordinate.
int nearestTablePixel(float coordinate)
{
  return static_cast<int>(coordinate + (kRoundingOffset + 0.5f)) - static_cast<int>(kRoundingOffset);
}
}  // namespace

void ParticleFilter::measure(int v_index, const RadialScanner& scanner)
{
  VParticle& v = v_[v_index];
  // The V-particle's measurement: 8 feature rays (k * 45 deg) and the two
  // further triangle rays (120, 240 deg); ray 0 serves both.
  float v_dist[kFeatureRays + 2];
  bool v_valid[kFeatureRays + 2];
  RayHit hits[kFeatureRays];
  scanFeatureRays(scanner, v.x, v.y, v.theta, hits);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    v_dist[k] = hits[k].distance;
    v_valid[k] = hits[k].valid;
  }
  v.rays = raySignature(hits);
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const RayHit hit = scanner.scanAngle(v.x, v.y, v.theta + t * kTriangleBinStep * kBinAngle);
    v_dist[kFeatureRays + t - 1] = hit.distance;
    v_valid[kFeatureRays + t - 1] = hit.valid;
  }

  // Spec "Motion model": an M-particle that has left its prototype is
  // re-seeded, in index order, before the update.
  const std::size_t begin = static_cast<std::size_t>(v_index) * mParticlesPerV();
  const std::size_t end = begin + mParticlesPerV();
  for (std::size_t i = begin; i < end; ++i)
  {
    const Prototype& p = (*memory_)[m_.prototype[i]];
    const int xi = nearestTablePixel(m_.x[i]), yi = nearestTablePixel(m_.y[i]);
    if (xi < 0 || yi < 0 || xi >= p.width() || yi >= p.height())
      seedM(m_, i, m_.prototype[i], v.rays);
  }
  measureRelational(v, v_dist, v_valid, begin, end);
}

namespace
{
/// The end points of a V-particle's rays in the input image: the 8 feature
/// rays and the triangle (ray 0 and the rays at 120 and 240 deg).
struct VRayEnds
{
  float feature_x[kFeatureRays];
  float feature_y[kFeatureRays];
  const bool* feature_valid;  // kFeatureRays entries
  int invalid_features = 0;
  float triangle_x[kTriangleRays];
  float triangle_y[kTriangleRays];
  bool triangle_valid = false;
};

/// `v_dist`/`v_valid`: the 8 feature rays, then the 2 further triangle rays.
VRayEnds rayEnds(const VParticle& v, const float* v_dist, const bool* v_valid)
{
  VRayEnds ends;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const double a = v.theta + k * kFeatureBinStep * kBinAngle;
    ends.feature_x[k] = static_cast<float>(v.x + v_dist[k] * std::cos(a));
    ends.feature_y[k] = static_cast<float>(v.y + v_dist[k] * std::sin(a));
  }
  ends.triangle_x[0] = ends.feature_x[0];
  ends.triangle_y[0] = ends.feature_y[0];
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const double a = v.theta + t * kTriangleBinStep * kBinAngle;
    ends.triangle_x[t] = static_cast<float>(v.x + v_dist[kFeatureRays + t - 1] * std::cos(a));
    ends.triangle_y[t] = static_cast<float>(v.y + v_dist[kFeatureRays + t - 1] * std::sin(a));
  }
  ends.triangle_valid = v_valid[0] && v_valid[kFeatureRays] && v_valid[kFeatureRays + 1];
  ends.feature_valid = v_valid;
  for (int k = 0; k < kFeatureRays; ++k)
    ends.invalid_features += v_valid[k] ? 0 : 1;
  return ends;
}

/// The settings of the relational update, in the precision of the hot loop.
struct RelationalSettings
{
  float log_invalid;
  float min_area;   // px^2, of either triangle
  float max_scale;  // of the affine's singular values
  bool image_space;
};

/// The triangle affine B (table -> image) of the relational particle (v, m)
/// at table pixel (xi, yi) and bin `bin`, and its inverse A (paper 4.1);
/// false when a triangle is degenerate, B mirrors, or its scale is out of bounds.
bool relationalAffine(const VRayEnds& ends, const std::uint8_t* raw, int xi, int yi, int bin,
                      const RelationalSettings& s, float b_map[6], float a[6])
{
  const BinDirections& dir = binDirections();
  const float unit = Prototype::kDistanceUnit;
  float mt_x[3], mt_y[3];
  for (int t = 0; t < kTriangleRays; ++t)
  {
    const int b = (bin + t * kTriangleBinStep) % kDirectionBins;
    if (raw[b] == Prototype::kNoEdge)
      return false;
    mt_x[t] = xi + raw[b] * unit * dir.cos[b];
    mt_y[t] = yi + raw[b] * unit * dir.sin[b];
  }
  if (!affineFromTriangles(mt_x, mt_y, ends.triangle_x, ends.triangle_y, s.min_area, s.min_area, b_map))
    return false;
  // A physical print is never mirrored, and its scale stays within bounds.
  const float det = b_map[0] * b_map[4] - b_map[1] * b_map[3];
  const float frob = b_map[0] * b_map[0] + b_map[1] * b_map[1] + b_map[3] * b_map[3] + b_map[4] * b_map[4];
  // Singular values s1 >= s2: s1^2 + s2^2 = frob, s1 s2 = det.
  const float disc = std::sqrt(std::max(0.f, frob * frob - 4.f * det * det));
  const float s1 = std::sqrt(0.5f * (frob + disc)), s2 = std::sqrt(std::max(0.f, 0.5f * (frob - disc)));
  if (det <= 0.f || s1 > s.max_scale || s2 < 1.f / s.max_scale)
    return false;
  // A = B^-1: input image -> prototype table.
  const float inv = 1.f / det;
  a[0] = b_map[4] * inv;
  a[1] = -b_map[1] * inv;
  a[3] = -b_map[3] * inv;
  a[4] = b_map[0] * inv;
  a[2] = -(a[0] * b_map[2] + a[1] * b_map[5]);
  a[5] = -(a[3] * b_map[2] + a[4] * b_map[5]);
  return true;
}

/// Paper eq. 6 over the 8 feature rays; dw_j of eq. 5 in input px
/// (B p'_j - p_j) or, as in the paper, in prototype px (p'_j - A p_j).
float relationalLogLikelihood(const VRayEnds& ends, const std::uint8_t* raw, int xi, int yi, int bin,
                              const float b_map[6], const float a[6], const RelationalSettings& s,
                              const ObservationModel& observation)
{
  const BinDirections& dir = binDirections();
  const float unit = Prototype::kDistanceUnit;
  float log_l = ends.invalid_features * s.log_invalid;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    if (!ends.feature_valid[k])
      continue;
    const int b = (bin + k * kFeatureBinStep) % kDirectionBins;
    if (raw[b] == Prototype::kNoEdge)
    {
      log_l += s.log_invalid;
      continue;
    }
    const float qx = xi + raw[b] * unit * dir.cos[b], qy = yi + raw[b] * unit * dir.sin[b];
    float dx, dy;
    if (s.image_space)
    {
      dx = b_map[0] * qx + b_map[1] * qy + b_map[2] - ends.feature_x[k];
      dy = b_map[3] * qx + b_map[4] * qy + b_map[5] - ends.feature_y[k];
    }
    else
    {
      dx = a[0] * ends.feature_x[k] + a[1] * ends.feature_y[k] + a[2] - qx;
      dy = a[3] * ends.feature_x[k] + a[4] * ends.feature_y[k] + a[5] - qy;
    }
    log_l += observation.logRayFromSquared(dx * dx + dy * dy);
  }
  return log_l;
}
}  // namespace

// The update of every relational particle (v, m) of M-particles [begin, end),
// each inside its prototype's table: the triangle affine of paper 4.1 and the
// likelihood of eqs. 5-6. Writes affine, affine_valid and log_likelihood.
void ParticleFilter::measureRelational(const VParticle& v, const float* v_dist, const bool* v_valid,
                                       std::size_t begin, std::size_t end)
{
  const VRayEnds ends = rayEnds(v, v_dist, v_valid);
  RelationalSettings settings;
  settings.log_invalid = static_cast<float>(observation_.logInvalid());
  settings.min_area = static_cast<float>(params_.min_triangle_area);
  settings.max_scale = static_cast<float>(params_.max_affine_scale);
  settings.image_space = params_.deviation_space == DeviationSpace::kImage;
  const float all_invalid = kFeatureRays * settings.log_invalid;

  for (std::size_t i = begin; i < end; ++i)
  {
    const Prototype& p = (*memory_)[m_.prototype[i]];
    const int xi = nearestTablePixel(m_.x[i]), yi = nearestTablePixel(m_.y[i]);
    m_.affine_valid[i] = 0;
    const int bin = angleToBin(m_.theta[i]);
    const std::uint8_t* raw = p.rawDistances(xi, yi);
    float b_map[6], a[6];  // B: prototype table -> image; A = B^-1
    if (!ends.triangle_valid || !relationalAffine(ends, raw, xi, yi, bin, settings, b_map, a))
    {
      m_.log_likelihood[i] = all_invalid;
      continue;
    }
    for (int e = 0; e < 6; ++e)
      m_.affine[e][i] = a[e];
    m_.affine_valid[i] = 1;
    m_.log_likelihood[i] = relationalLogLikelihood(ends, raw, xi, yi, bin, b_map, a, settings, observation_);
  }
}
}  // namespace amcr
