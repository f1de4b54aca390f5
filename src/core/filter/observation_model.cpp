#include "amcr/filter/observation_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "amcr/base/errors.h"
#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/relational_update.h"
#include "amcr/memory/prototype_memory.h"

namespace amcr
{
namespace
{
constexpr int kTableEntries = 4096;  // tabulated over dw^2 in [0, (8 sigma_w)^2]

void storeAffine(const RelationalAffine& affine, MParticleSet& m, std::size_t i)
{
  for (int e = 0; e < 6; ++e)
    m.affine[e][i] = affine.image_to_table[e];
  m.affine_valid[i] = kFittedAffine;
}
}  // namespace

AffineFitRule::AffineFitRule(const ObservationParams& params)
  : min_triangle_area(static_cast<float>(params.min_triangle_area))
  , max_affine_scale(static_cast<float>(params.max_affine_scale))
  , deviation_space(params.deviation_space)
  , ray_correspondence(params.ray_correspondence)
  , affine_refits(params.affine_refits)
{
}

ObservationModel::ObservationModel(const ObservationParams& params, const ScanParams& scan)
  : sigma_w_(params.sigma_w)
  , p_outlier_(params.p_outlier)
  , outlier_density_(params.likelihood_form == LikelihoodForm::kPaper ? params.p_outlier
                                                                       : params.p_outlier / scan.max_ray_length)
  , log_invalid_(std::log(std::max(params.likelihood_form == LikelihoodForm::kPaper
                                        ? params.p_invalid
                                        : params.p_invalid / scan.max_ray_length,
                                    1e-300)))
  , fit_(params)
{
  const double max_squared = 64.0 * sigma_w_ * sigma_w_;
  const double step = max_squared / (kTableEntries - 1);
  inv_step_ = static_cast<float>(1.0 / step);
  table_.resize(kTableEntries);
  for (int i = 0; i < kTableEntries; ++i)
    table_[i] = static_cast<float>(logRay(std::sqrt(i * step)));
  log_far_ = static_cast<float>(logRay(1e6 * sigma_w_));
  for (int i = 0; i + 1 < kTableEntries; ++i)
    cell_start_slope_.insert(cell_start_slope_.end(), {table_[i], table_[i + 1] - table_[i]});
  cell_start_slope_.insert(cell_start_slope_.end(), {log_far_, 0.f, static_cast<float>(log_invalid_), 0.f});
}

// Paper eq. 5: p(dw) = p_outlier + (1 - p_outlier) N(dw; 0, sigma_w^2); the
// mixture form divides p_outlier by the largest deviation L so that p is a density.
double ObservationModel::logRay(double dw) const
{
  const double gauss = std::exp(-dw * dw / (2.0 * sigma_w_ * sigma_w_)) / (sigma_w_ * std::sqrt(2.0 * M_PI));
  return std::log(std::max(outlier_density_ + (1.0 - p_outlier_) * gauss, 1e-300));
}

void ObservationModel::measureReference(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m,
                                        std::size_t begin, std::size_t end) const
{
  const float all_invalid = kFeatureRays * static_cast<float>(log_invalid_);
  for (std::size_t i = begin; i < end; ++i)
  {
    const Prototype& p = memory[m.prototype[i]];
    const cv::Point at = nearestTablePixel(m.x[i], m.y[i]);
    if (!insideTable(p, at))
      throw InputError("ObservationModel::measure: M-particle " + std::to_string(i) + " lies outside the table of '" +
                       p.label() + "'");
    m.affine_valid[i] = kNoAffine;
    m.log_likelihood[i] = all_invalid;
    if (!v.triangle_valid)
      continue;
    const std::uint8_t* raw = p.rawDistances(at.x, at.y);
    RelationalAffine affine;
    if (fit_.ray_correspondence == RayCorrespondence::kAffine)
    {
      // The first lookup assumes the V-particle's view shape, turned onto the
      // M-particle's heading; the fixed point of fitCorrectedAffine refines it.
      const float assumed[4] = {m.shape[0][i], m.shape[1][i], m.shape[1][i], m.shape[2][i]};
      float shape[4];
      startingShape(assumed, m.theta[i], v.feature_dx[0], v.feature_dy[0], shape);
      if (!fitCorrectedAffine(raw, at, shape, v, fit_.affine_refits, fit_.min_triangle_area, fit_.max_affine_scale, affine))
        continue;
      linearPart(affine, shape);
      storeAffine(affine, m, i);
      m.log_likelihood[i] = correctedLogLikelihood(v, raw, at, shape, affine);
      continue;
    }
    const int bin = angleToBin(m.theta[i]);
    float table_x[kTriangleRays], table_y[kTriangleRays];
    if (!tableTriangle(raw, at, bin, table_x, table_y) ||
        !fitRelationalAffine(table_x, table_y, v, fit_.min_triangle_area, fit_.max_affine_scale, affine))
      continue;
    storeAffine(affine, m, i);
    m.log_likelihood[i] = logLikelihood(v, raw, at, bin, affine);
  }
}

// Paper eq. 6 with the affine-corrected lookups of corrected_scan.h: feature
// ray k is compared with the table ray of direction L d_k.
float ObservationModel::correctedLogLikelihood(const VRayEnds& v, const std::uint8_t* raw, const cv::Point& at,
                                               const float shape[4], const RelationalAffine& affine) const
{
  return featureRaysLogLikelihood(v, affine, [&](int k, float& x, float& y) {
    return correctedRayEnd(raw, at, tableDirection(shape, v.feature_dx[k], v.feature_dy[k]), x, y);
  });
}

float ObservationModel::logLikelihood(const VRayEnds& v, const std::uint8_t* raw, const cv::Point& at, int bin,
                                      const RelationalAffine& affine) const
{
  return featureRaysLogLikelihood(v, affine, [&](int k, float& x, float& y) {
    return tableRayEnd(raw, at, (bin + k * kFeatureBinStep) % kDirectionBins, x, y);
  });
}

// Paper eq. 6: the product over the feature rays of p(dw_j) (eq. 5) for a ray
// valid on both sides, p_invalid for the others; summed in logs.
template <typename TableEnd>
float ObservationModel::featureRaysLogLikelihood(const VRayEnds& v, const RelationalAffine& affine,
                                                 TableEnd table_end) const
{
  const float log_invalid = static_cast<float>(log_invalid_);
  float log_l = v.invalid_feature_rays * log_invalid;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    if (!v.feature_valid[k])
      continue;
    float table_x, table_y;
    if (!table_end(k, table_x, table_y))
    {
      log_l += log_invalid;
      continue;
    }
    const float dw_squared =
        squaredDeviation(affine, fit_.deviation_space, table_x, table_y, v.feature_x[k], v.feature_y[k]);
    log_l += logRayFromSquared(dw_squared);
  }
  return log_l;
}
}  // namespace amcr
