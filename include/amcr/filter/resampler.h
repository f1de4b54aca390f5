// The resampling of the particle filter (paper 3.6): the M-particles of one
// V-particle after its update (SIR over every prototype, with a share
// re-seeded, a share placed at the leading hypotheses' poses, and the size
// of the next generation by KLD-sampling), and the draw of the next
// V-particles every w iterations, with the attention feedback of paper 4.3.
// It owns the V-resampling's random stream, the leading hypotheses and the
// M-particle set the next generation is written into. Reads
// ParticleCounts' KLD-sampling (kld_error, kld_z, min_m_particles_per_v),
// ResamplingParams (injection_fraction, m_reseed_fraction,
// v_reseed_fraction) and MotionParams' noise of an injected pose
// (motion_noise_translation, motion_noise_rotation).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/held_objects.h"
#include "amcr/filter/particle_seeder.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/v_workspace.h"

namespace amcr
{
/// A leading hypothesis of the result extraction: a prototype at an
/// image -> table affine, whose implied poses are injected as M-particles.
struct LeadingHypothesis
{
  int prototype = -1;
  Affine image_to_table;
};

/// The next generation of V-particles, slot by slot.
struct VGeneration
{
  std::vector<int> source;  ///< the V-particle each slot copies, or -1: seeded afresh
  std::vector<bool> turned;  ///< the copy turns to a random heading (not the first copy of its source)
};

class Resampler
{
public:
  /// The V-resampling's stream starts from `seed`.
  Resampler(const ParticleCounts& counts, const ResamplingParams& resampling, const MotionParams& motion,
            std::uint64_t seed);

  /// Forgets the leading hypotheses and the scratch set; the V-resampling's
  /// stream starts again from `seed`.
  void reset(std::uint64_t seed);

  /// The hypotheses whose poses the following M-resamplings inject.
  void setLeading(std::vector<LeadingHypothesis> leading) { leading_ = std::move(leading); }
  void clearLeading() { leading_.clear(); }

  /// Resamples the `count` M-particles of `v` at [begin, begin + count) of
  /// `m` (its slots: `capacity` from begin) by their likelihoods times
  /// their proposal weights; re-seeded ones come from `seeder` in `scene`.
  /// Returns how many it holds now.
  int resampleM(const VParticle& v, MParticleSet& m, std::size_t begin, int count, int capacity,
                const ParticleSeeder& seeder, const SeedingScene& scene, VWorkspace& work);

  /// Which V-particle each slot of the next generation copies, by the
  /// V-particles' evidence, with the weight of each reported object's
  /// V-particles (`object_v_particles`, V indices) shared beyond a number
  /// per object and the V-particles `held` keeps carried over first.
  VGeneration drawV(const std::vector<VParticle>& v, const std::vector<std::vector<int>>& object_v_particles,
                    const HeldObjects& held);

  /// The set the next generation is written into (as large as the
  /// filter's), swapped with the filter's set after a V-resampling.
  MParticleSet& scratch() { return scratch_; }

private:
  /// KLD-sampling (Fox 2003): how many M-particles the next generation of
  /// a V-particle needs, given `picks` drawn from the current one.
  int kldCount(const MParticleSet& m, const std::vector<int>& picks, std::size_t begin, int capacity,
               std::vector<std::uint64_t>& bins) const;
  /// Places M-particle `index` of the scratch set at the pose leading
  /// hypothesis `h` implies for V-particle `v`, with likelihood `worst`.
  void injectM(const VParticle& v, const LeadingHypothesis& h, std::size_t index, float worst,
               const ParticleSeeder& seeder, const SeedingScene& scene, VWorkspace& work);
  /// Each V-particle's log V-weight (attention feedback).
  std::vector<double> attentionWeights(const std::vector<VParticle>& v,
                                       const std::vector<std::vector<int>>& object_v_particles) const;

  double kld_error_;
  double kld_z_;
  int min_m_particles_;  // min_m_particles_per_v
  double injection_fraction_;
  double m_reseed_fraction_;
  double v_reseed_fraction_;
  double noise_translation_;  // motion_noise_translation, prototype px
  double noise_rotation_;     // motion_noise_rotation, rad
  Rng rng_;                                 // the V-resampling's draw
  std::vector<LeadingHypothesis> leading_;  // injected at the M-resamplings
  MParticleSet scratch_;
};
}  // namespace amcr
