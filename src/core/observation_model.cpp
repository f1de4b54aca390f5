#include "amcr/observation_model.h"

#include <cmath>

namespace amcr
{
namespace
{
constexpr int kTableEntries = 4096;  // tabulated over dw^2 in [0, (8 sigma_w)^2]
}

ObservationModel::ObservationModel(const Params& params)
  : sigma_w_(params.sigma_w)
  , p_outlier_(params.p_outlier)
  , outlier_density_(params.likelihood_form == LikelihoodForm::kPaper ? params.p_outlier
                                                                       : params.p_outlier / params.max_ray_length)
  , log_invalid_(std::log(std::max(params.p_invalid, 1e-300)))
{
  const double max_squared = 64.0 * sigma_w_ * sigma_w_;
  const double step = max_squared / (kTableEntries - 1);
  inv_step_ = static_cast<float>(1.0 / step);
  table_.resize(kTableEntries);
  for (int i = 0; i < kTableEntries; ++i)
    table_[i] = static_cast<float>(logRay(std::sqrt(i * step)));
  log_far_ = static_cast<float>(logRay(1e6 * sigma_w_));
}

// Paper eq. 5: p(dw) = p_outlier + (1 - p_outlier) N(dw; 0, sigma_w^2); the
// mixture form divides p_outlier by the largest deviation L so that p is a density.
double ObservationModel::logRay(double dw) const
{
  const double gauss = std::exp(-dw * dw / (2.0 * sigma_w_ * sigma_w_)) / (sigma_w_ * std::sqrt(2.0 * M_PI));
  return std::log(std::max(outlier_density_ + (1.0 - p_outlier_) * gauss, 1e-300));
}

// Paper eq. 6: the product over valid rays of p(dw_j) times p_invalid per invalid ray.
double ObservationModel::logLikelihood(const float* dw, const bool* valid, int n) const
{
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    sum += valid[j] ? logRay(dw[j]) : log_invalid_;
  return sum;
}
}  // namespace amcr
