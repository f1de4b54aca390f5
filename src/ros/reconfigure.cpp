#include "reconfigure.h"

namespace amcr_ros
{
// The numeric fields of cfg/AMCR.cfg (test/test_reconfigure_table.cpp checks
// that they are exactly amcr::parameterTable()).
#define AMCR_RECONFIGURE_FIELDS(X)                                                                             \
  X(num_v_particles) X(m_particles_per_prototype) X(prototype_size) X(max_ray_length) X(edge_threshold)        \
  X(blur_sigma) X(sigma_w) X(p_outlier) X(p_invalid) X(min_triangle_area) X(max_affine_scale) X(v_step)        \
  X(motion_noise_translation) X(motion_noise_rotation) X(reflection_jitter) X(v_resample_interval)             \
  X(v_reseed_fraction) X(m_reseed_fraction) X(injection_fraction) X(seed_enclosure_rays) X(seed_attempts)      \
  X(cluster_radius) X(cluster_min_share) X(group_tolerance) X(min_support) X(refine_iterations)                \
  X(refine_search) X(decision_threshold) X(min_object_size) X(optical_flow) X(flow_window) X(flow_levels) \
  X(flow_max_error) X(frame_budget_ms) X(seed)

amcr::AMCRConfig toConfig(const amcr::Params& params)
{
  amcr::AMCRConfig config = amcr::AMCRConfig::__getDefault__();
#define AMCR_TO_CONFIG(name) config.name = static_cast<decltype(config.name)>(amcr::getParameter(params, #name));
  AMCR_RECONFIGURE_FIELDS(AMCR_TO_CONFIG)
#undef AMCR_TO_CONFIG
  config.likelihood_form = amcr::toString(params.likelihood_form);
  config.deviation_space = amcr::toString(params.deviation_space);
  config.prototype_priors = amcr::formatPriors(params.prototype_priors);
  return config;
}

amcr::Params fromConfig(const amcr::AMCRConfig& config, amcr::Params params)
{
#define AMCR_FROM_CONFIG(name) amcr::setParameter(params, #name, static_cast<double>(config.name));
  AMCR_RECONFIGURE_FIELDS(AMCR_FROM_CONFIG)
#undef AMCR_FROM_CONFIG
  amcr::setParameter(params, "likelihood_form", config.likelihood_form);
  amcr::setParameter(params, "deviation_space", config.deviation_space);
  amcr::setParameter(params, "prototype_priors", config.prototype_priors);
  return params;
}

bool tablesDiffer(const amcr::Params& a, const amcr::Params& b)
{
  return a.prototype_size != b.prototype_size || a.edge_threshold != b.edge_threshold ||
         a.blur_sigma != b.blur_sigma;
}
}  // namespace amcr_ros
