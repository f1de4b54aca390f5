#include "amcr/filter/attention_control.h"

#include <utility>

#include "amcr/base/errors.h"

namespace amcr
{
AttentionControl::AttentionControl(const AttentionParams& attention, const MotionParams& motion,
                                   const ExtractionParams& clusters)
  : policy_(std::make_unique<ReflectAtEdgesPolicy>(motion.v_step, motion.reflection_jitter))
  , discriminator_(motion.v_step, attention.discriminative_min_gain)
  , discriminative_moves_(attention.discriminative_moves)
  , competing_fits_(clusters.competing_fits > 0)
  , cluster_radius_(static_cast<float>(clusters.cluster_radius))
  , competing_min_share_(static_cast<float>(attention.discriminative_min_share))
  , converged_share_(static_cast<float>(clusters.cluster_min_share))
{
}

void AttentionControl::setPolicy(std::unique_ptr<ExplorationPolicy> policy)
{
  if (!policy)
    throw ParameterError("the exploration policy must not be null");
  policy_ = std::move(policy);
}

// To where competing clusters disagree (paper 4.3's feedback control,
// discriminative_attention.h), else from the policy.
Control AttentionControl::decide(VParticle& v, const MParticleSet& m, const MRange& r, const FilterMemory& memory,
                                 const ObservationModel& observation, const cv::Size& image_size,
                                 const RadialScanner& scanner, Rng& rng) const
{
  Control u;
  v.competing = CompetingHypotheses();
  v.discriminating = false;
  if (discriminative_moves_ || competing_fits_)
  {
    const CompetingHypotheses competing =
        competingHypotheses(m, r, v.x, v.y, cluster_radius_, competing_min_share_);
    if (decidingBetweenLookAlikes(competing, converged_share_))
      v.competing = competing;
    DiscriminativeMove move;
    if (discriminative_moves_ && discriminator_.choose(v, v.competing, *memory.memory(), observation, image_size,
                                                       memory.places().get(), move))
    {
      u = move.control;
      v.discriminating = true;
    }
  }
  if (!v.discriminating)
    u = policy_->decide(v, scanner, rng);
  return u;
}
}  // namespace amcr
