// The observation model O of Radial-AMCR (paper eqs. 5-6), in log space.
#pragma once

#include <vector>

#include "amcr/params.h"

namespace amcr
{
class ObservationModel
{
public:
  /// Reads sigma_w, p_outlier, p_invalid, likelihood_form and max_ray_length.
  explicit ObservationModel(const Params& params);

  /// log p(dw) of one valid ray with deviation dw px (paper eq. 5, or the
  /// normalised mixture).
  double logRay(double dw) const;

  /// log p_invalid, the term of a ray with no edge on either side (eq. 6).
  double logInvalid() const { return log_invalid_; }

  /// Fast log p(dw) from the squared deviation, interpolated in a table
  /// (equal to logRay within 1e-4).
  float logRayFromSquared(float dw_squared) const
  {
    const float index = dw_squared * inv_step_;
    if (!(index < static_cast<float>(table_.size() - 1)))
      return log_far_;
    const std::size_t i = static_cast<std::size_t>(index);
    const float f = index - static_cast<float>(i);
    return table_[i] + f * (table_[i + 1] - table_[i]);
  }

  /// log p(z | x) of eq. 6 for `n` rays: valid[j] says whether both rays met
  /// an edge, dw[j] is the deviation of a valid ray.
  double logLikelihood(const float* dw, const bool* valid, int n) const;

private:
  double sigma_w_;
  double p_outlier_;
  double outlier_density_;
  double log_invalid_;
  float log_far_;
  float inv_step_;
  std::vector<float> table_;
};
}  // namespace amcr
