// Where the particle filter's new particles start (paper 3.6, spec "Where
// V-particles start matters" and "Beyond the paper"): a V-particle at a
// place enclosed by edges outside the held objects; its M-particles spread
// over the prototypes by the prior, each uniformly inside its prototype (the
// paper) or, for a share index_share, at a place the proposal indexes find
// for the V-particle's rays (the mixture proposal), with the importance
// weight of the mixture; with ray_correspondence affine, a view shape.
// Reads ResamplingParams' seed_attempts and seed_enclosure_rays,
// ProposalParams (index_share, proposal_correction, index_stride,
// index_candidates) and ObservationParams' view shapes (ray_correspondence,
// max_anisotropy, oblique_share). Keeps no state: what it draws comes from
// the V-particle slot's stream.
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/held_objects.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/filter/v_workspace.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// What new particles are drawn from besides a random stream: the memory
/// made ready for the filter (prototypes, prior, indexes), the objects held
/// (places to avoid, prototypes to lean towards) and the image's size.
struct SeedingScene
{
  const FilterMemory& memory;
  const HeldObjects& held;
  cv::Size image_size;
};

class ParticleSeeder
{
public:
  /// `log_invalid`: the log likelihood of an invalid ray (ObservationModel),
  /// which each ray of a new M-particle has until it is measured.
  ParticleSeeder(const ResamplingParams& resampling, const ProposalParams& proposals,
                 const ObservationParams& observation, double log_invalid);

  /// A new V-particle (a pose on the scanner's image) and its M-particles in
  /// [begin, end) of `set`, their prototypes from the prior slots.
  void seedVAndM(VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end, const RadialScanner& scanner,
                 const SeedingScene& scene, VWorkspace& work) const;
  /// The same with the V-particle at `place` (an image candidate's place):
  /// only where the V-particle starts differs, its M-particles are seeded
  /// and weighted as seedVAndM's.
  void seedVAndMAt(const RayPlace& place, VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end,
                   const RadialScanner& scanner, const SeedingScene& scene, VWorkspace& work) const;
  /// A new M-particle at `index` of `set`: with probability index_share
  /// (when work.candidates holds places) at one of them, else uniformly in
  /// `prototype` as in the paper; with the importance weight of the mixture.
  void seedM(MParticleSet& set, std::size_t index, int prototype, const VParticle& v, const SeedingScene& scene,
             VWorkspace& work) const;
  /// The places of the memory the V-particle's rays look like (into
  /// work.candidates): its own rays, and with oblique view shapes on, its
  /// rays read under one drawn view shape.
  void findCandidates(const VParticle& v, const RadialScanner& scanner, const FilterMemory& memory,
                      VWorkspace& work) const;
  /// Frontal candidates kept from the radial-profile index.
  static constexpr int kProfileCandidates = 8;

private:
  /// The places V-particle `v` is proposed seen frontally, best first: from
  /// the radial-profile index when it is on and the V-particle's profile
  /// can be read (the best aligned kProfileCandidates), else from the 8-ray
  /// index (`count` of them); empty without an index.
  std::vector<ProposalCandidate> frontalCandidates(const VParticle& v, const RadialScanner& scanner,
                                                   const FilterMemory& memory, int count) const;
  void seedV(VParticle& v, const RadialScanner& scanner, const SeedingScene& scene, Rng& rng) const;
  /// The M-particles of a V-particle just placed, in [begin, end) of `set`.
  void seedMOf(const VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end, const RadialScanner& scanner,
               const SeedingScene& scene, VWorkspace& work) const;
  void seedUniform(MParticleSet& set, std::size_t index, int prototype, const VParticle& v,
                   const PrototypeMemory& memory, Rng& rng) const;
  void seedAtCandidate(MParticleSet& set, std::size_t index, const ProposalCandidate& c,
                       const PrototypeMemory& memory, Rng& rng) const;
  /// A new M-particle has no affine yet, and the likelihood of all rays invalid.
  void clearMeasurement(MParticleSet& set, std::size_t index) const;
  /// log(seeding density / mixture density) at M-particle `index` of `set`.
  float logProposalWeight(const MParticleSet& set, std::size_t index, double share,
                          const std::vector<ProposalCandidate>& candidates, const SeedingScene& scene) const;
  /// ray_correspondence affine: gives M-particle `index` a view shape,
  /// frontal or drawn (corrected_scan.h); true when it is not frontal.
  bool drawShape(MParticleSet& set, std::size_t index, Rng& rng) const;
  /// An oblique view shape: anisotropy log-uniform in [1, max_anisotropy]
  /// along a uniform axis.
  void drawObliqueShape(Rng& rng, float shape[3]) const;

  int seed_attempts_;
  int seed_enclosure_rays_;
  double index_share_;
  double proposal_correction_;
  int index_stride_;
  int index_candidates_;
  RayCorrespondence ray_correspondence_;
  double max_anisotropy_;
  double oblique_share_;
  double log_invalid_;
};
}  // namespace amcr
