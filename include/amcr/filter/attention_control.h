// Where a V-particle looks next (paper 4.3, the feedback control u = F(z)):
// when its M-particles hold competing clusters of look-alike prototypes and
// discriminative_moves is on, the move whose predicted scans tell them apart
// (discriminative_attention.h); otherwise the exploration policy's move.
// Reads AttentionParams (discriminative_moves, discriminative_min_share,
// discriminative_min_gain), MotionParams (v_step, reflection_jitter) and of
// ExtractionParams what makes a cluster: competing_fits, cluster_radius and
// cluster_min_share.
#pragma once

#include <memory>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/discriminative_attention.h"
#include "amcr/filter/exploration_policy.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/motion_model.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
class AttentionControl
{
public:
  /// The policy is the paper's (ReflectAtEdgesPolicy) until setPolicy().
  AttentionControl(const AttentionParams& attention, const MotionParams& motion, const ExtractionParams& clusters);

  /// Replaces the exploration policy F (ParameterError when null).
  void setPolicy(std::unique_ptr<ExplorationPolicy> policy);

  /// The control of `v` in this iteration, its M-particles `r` of `m` on
  /// `memory`'s prototypes, in an image of `image_size`; sets v.competing
  /// (the clusters it is deciding between, when they are look-alikes) and
  /// v.discriminating (whether they chose the move). Called for several
  /// V-particles at once, each with its own stream `rng`.
  Control decide(VParticle& v, const MParticleSet& m, const MRange& r, const FilterMemory& memory,
                 const ObservationModel& observation, const cv::Size& image_size, const RadialScanner& scanner,
                 Rng& rng) const;

private:
  std::unique_ptr<ExplorationPolicy> policy_;
  DiscriminativeMoveChooser discriminator_;  // used when discriminative_moves
  bool discriminative_moves_;
  bool competing_fits_;         // competing_fits > 0: the extraction reads v.competing
  float cluster_radius_;        // table px
  float competing_min_share_;   // discriminative_min_share
  float converged_share_;       // cluster_min_share
};
}  // namespace amcr
