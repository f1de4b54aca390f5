// The particle filter of Radial-AMCR (paper 3.6, spec "State"): V-particles
// in the input image, each with its M-particles in the prototypes (the map
// R^-1(v)). The filter keeps the particle sets and the order of an
// iteration; its collaborators own their state and read their own
// parameters:
// - AttentionControl (attention_control.h): a V-particle's control, from
//   the exploration policy or the discriminative moves (paper 4.3);
// - MotionModel (paper 4.2) and ObservationModel (paper 4.1, eqs. 5-6);
// - ParticleSeeder (particle_seeder.h): where new V- and M-particles start,
//   with the mixture proposal from the memory's indexes;
// - Resampler (resampler.h): M-resampling with the injection of leading
//   hypotheses and KLD-sampling, and the draw of the next V-particles;
// - HeldObjects (held_objects.h): inhibition of return and the scene's context;
// - FilterMemory (filter_memory.h): the memory with its prior and indexes.
//
// Every draw of a recognizer is made here: one stream per V-particle slot
// (VWorkspace), for everything a V-particle's iteration, seeding or
// resampling draws, and the Resampler's one for the V-resampling's draw.
// The V-particles' iterations are independent and run on params.num_threads
// threads; a V-particle's draws come from its own stream, so the result is
// the same for any thread count (same seed, same output, on any machine).
//
// What it learns from the result extraction comes in explicitly: evidence
// per V-particle (addEvidence), the leading hypotheses to inject (setLeading)
// and the V-particles of each reported object (resampleV).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/filter/attention_control.h"
#include "amcr/filter/exploration_policy.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/held_objects.h"
#include "amcr/filter/motion_model.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particle_seeder.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/filter/resampler.h"
#include "amcr/filter/v_workspace.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
class ParticleFilter
{
public:
  /// Takes validated `params` and a memory with at least one prototype
  /// (MemoryError otherwise); ParameterError from the prior (PrototypePrior).
  /// The filter is empty until seed().
  ParticleFilter(const Params& params, std::shared_ptr<const PrototypeMemory> memory);
  /// The same with the memory made ready beforehand (its parameters are the filter's).
  explicit ParticleFilter(FilterMemory memory);

  /// Replaces the exploration policy F (ParameterError when null).
  void setPolicy(std::unique_ptr<ExplorationPolicy> policy) { attention_.setPolicy(std::move(policy)); }

  /// Swaps the memory (as the constructor checks it) and empties the filter.
  /// On an error the filter keeps its memory.
  void setMemory(std::shared_ptr<const PrototypeMemory> memory);
  /// The same with a memory made ready beforehand: no build, only the swap.
  /// ParameterError when it was built for other parameters than the
  /// filter's. Returns the memory it replaced (the caller frees it where
  /// that costs nobody: not under a lock).
  FilterMemory setMemory(FilterMemory memory);

  /// Swaps in a memory that extends the current one (prototypes added after
  /// the current ones, PrototypeMemory::isPrefixOf): the particles stay,
  /// their prototype indices still hold, and the prior and the proposal
  /// index are rebuilt, so the new prototypes are explored from the next
  /// iteration on. MemoryError when `memory` does not extend the current
  /// one; on an error the filter keeps its memory.
  void extendMemory(std::shared_ptr<const PrototypeMemory> memory);
  /// The same with a memory made ready beforehand (its prior and indexes
  /// are built already); ParameterError as setMemory(FilterMemory). Returns
  /// the memory it replaced.
  FilterMemory extendMemory(FilterMemory memory);

  /// Empties the filter and re-seeds the generator with params.seed.
  void reset();

  /// Whether seed() must run before an update on an image of `size`: the
  /// filter is empty, or it was seeded on an image of another size.
  bool needsSeeding(const cv::Size& size) const { return v_.empty() || size != image_size_; }

  /// Seeds params.num_v_particles V-particles and their M-particles on the
  /// scanner's image; forgets the leading hypotheses.
  void seed(const RadialScanner& scanner);

  /// One V-particle's iteration (paper 3.6): its control (AttentionControl),
  /// the motion of it and its M-particles, its measurement and the update of
  /// its M-particles (eqs. 5-6), its evidence, and the M-resampling.
  void update(int v_index, const RadialScanner& scanner);

  /// The iterations of V-particles [first, last), on params.num_threads
  /// threads: the same result as update() of each in index order. The
  /// exploration policy's decide() is called from several threads at once.
  void updateRange(int first, int last, const RadialScanner& scanner);

  /// Adds the verification's evidence to the V-particles it names.
  void addEvidence(const std::vector<EvidenceBonus>& evidence);

  /// The hypotheses whose poses the following M-resamplings inject.
  void setLeading(std::vector<LeadingHypothesis> leading) { resampler_.setLeading(std::move(leading)); }

  /// V-resampling (paper 3.6, every w iterations): draws V-particles by their
  /// evidence, with the weight of each reported object's V-particles
  /// (`object_v_particles`, V indices) shared beyond a number per object.
  /// The V-particles seeded afresh start at `seed_places` first, one each in
  /// slot order (the image's candidates, coverage_schedule.h), the rest at
  /// random (ParticleSeeder); their M-particles are seeded alike either way.
  /// Returns the ancestry: for each new V-particle the index of the one it
  /// copies, or -1 when it was seeded afresh.
  std::vector<int> resampleV(const RadialScanner& scanner, const std::vector<std::vector<int>>& object_v_particles,
                             const std::vector<RayPlace>& seed_places = {});

  /// The objects held in this frame (track_registry.h), replacing the last
  /// ones: no V-particle is seeded inside the convex hull of a held object's
  /// outline (inhibition of return), and V-resampling keeps at most
  /// params.held_v_particles of the V-particles on each (those inside the
  /// hull and those that support it), so that the rest look at what is not
  /// explained yet. A share params.scene_prior_share of the M-particles
  /// seeded from then on is drawn in the held objects' prototypes (the
  /// scene's context: copies of what is in view are likely; not in a
  /// prototype whose prior is 0). InputError, before anything changes, for a
  /// prototype index outside the memory.
  void setHeldObjects(const std::vector<HeldObject>& held);
  /// Index (in the last setHeldObjects) of the held object whose outline's
  /// convex hull holds (x, y), or -1.
  int heldObjectAt(float x, float y) const { return held_.at(x, y); }

  /// Moves the V-particles by the optical flow (one move per V-particle, in
  /// index order); a lost one is seeded afresh with new M-particles. Returns
  /// how many were lost.
  int applyFlow(const std::vector<VParticleMove>& moves, const RadialScanner& scanner);

  /// Moves every V-particle by an external displacement, kept inside the
  /// image; its M-particles stay where they are. InputError for a count
  /// other than the V-particles' or a displacement that is not finite.
  void displace(const std::vector<cv::Point2f>& displacement);

  const Params& params() const { return memory_.params(); }
  const PrototypeMemory& memory() const { return *memory_.memory(); }
  const std::vector<VParticle>& vParticles() const { return v_; }
  const MParticleSet& mParticles() const { return m_; }
  /// M-particle slots per V-particle (the budget): those of V-particle v
  /// start at v * mParticlesPerV().
  int mParticlesPerV() const { return static_cast<int>(memory_.prior().slots().size()); }
  /// The M-particles V-particle v holds now: mParticlesPerV() of them, or
  /// fewer under KLD-sampling.
  MRange mRange(int v) const;
  /// Each V-particle's M-particles (index = V index).
  std::vector<MRange> mRanges() const;
  /// The mean number of M-particles per V-particle now.
  double meanMParticles() const;
  /// The proposal index, or null when index_share is 0.
  const ProposalIndex* proposalIndex() const { return memory_.index().get(); }
  /// What the last memory's index build left out (a line per prototype).
  const std::vector<std::string>& indexWarnings() const { return memory_.warnings(); }
  /// The memory's look-alike pairs (discriminative_places.h), with their
  /// places when discriminative_moves and discriminative_places are on;
  /// null when competing_fits is 0 and the moves are off.
  const DiscriminativePlaces* lookAlikes() const { return memory_.places().get(); }
  /// The prototype of each of a V-particle's M-particle slots at seeding.
  const std::vector<int>& priorSlots() const { return memory_.prior().slots(); }
  /// The size of the image the filter was seeded on.
  const cv::Size& imageSize() const { return image_size_; }

private:
  /// What new particles are drawn from now.
  SeedingScene seedingScene() const { return SeedingScene{memory_, held_, image_size_}; }
  /// Swaps `memory` with the filter's own (no reset): afterwards `memory`
  /// holds the replaced one. ParameterError, before anything changes, when
  /// it was built for other parameters.
  void swapMemory(FilterMemory& memory);
  /// Scans the V-particle's rays (refreshing v.rays) and updates its
  /// M-particles by eqs. 5-6.
  void measure(int v_index, const RadialScanner& scanner);
  void accumulateEvidence(int v_index);

  FilterMemory memory_;
  AttentionControl attention_;
  ObservationModel observation_;
  MotionModel motion_;
  ParticleSeeder seeder_;
  Resampler resampler_;
  HeldObjects held_;
  std::vector<VWorkspace> work_;  // one per V-particle slot

  cv::Size image_size_;
  std::vector<VParticle> v_;
  MParticleSet m_;
  std::vector<int> m_count_;  // M-particles each V-particle holds
};
}  // namespace amcr
