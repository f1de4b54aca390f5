// The particle filter of Radial-AMCR (paper 3.6, spec "State"): V-particles
// in the input image, each with its M-particles in the prototypes (the map
// R^-1(v)); seeding, one V-particle's iteration (motion, measurement,
// M-resampling with the injection of leading hypotheses) and V-resampling
// with attention feedback. It owns the random generators of a recognizer:
// one stream per V-particle slot, for everything a V-particle's iteration,
// seeding or resampling draws, and one for the V-resampling's draw (every
// draw of a recognizer is made here). The V-particles' iterations are
// independent and run on params.num_threads threads; a V-particle's draws
// come from its own stream, so the result is the same for any thread count
// (same seed, same output, on any machine).
//
// What it learns from the result extraction comes in explicitly: evidence
// per V-particle (addEvidence), the leading hypotheses to inject (setLeading)
// and the V-particles of each reported object (resampleV).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/discriminative_attention.h"
#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/exploration_policy.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/motion_model.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/profile_index.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/prototype_prior.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// A leading hypothesis of the result extraction: a prototype at an
/// image -> table affine, whose implied poses are injected as M-particles.
struct LeadingHypothesis
{
  int prototype = -1;
  Affine image_to_table;
};

/// Log V-weight that the verification of a V-particle's interpretation adds
/// to its evidence (paper 4.3, attention feedback).
struct EvidenceBonus
{
  int v = -1;  ///< index of the V-particle
  double log_weight = 0.0;
};

/// An object that the tracker holds: what attention may leave alone.
struct HeldObject
{
  int prototype = -1;                ///< index into the memory
  std::vector<cv::Point2d> outline;  ///< px of the filter's image
  /// The V-particles that support it (V indices, valid until the next
  /// V-resampling), wherever they are.
  std::vector<int> v_particles;
};

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
  void setPolicy(std::unique_ptr<ExplorationPolicy> policy);

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

  /// One V-particle's iteration (paper 3.6): its control (from the
  /// discriminative attention when its M-particles hold competing clusters
  /// and params.discriminative_moves is on, else from the policy), the
  /// motion of it and its M-particles, its measurement and the update of its
  /// M-particles (eqs. 5-6), its evidence, and the M-resampling.
  void update(int v_index, const RadialScanner& scanner);

  /// The iterations of V-particles [first, last), on params.num_threads
  /// threads: the same result as update() of each in index order. The
  /// exploration policy's decide() is called from several threads at once.
  void updateRange(int first, int last, const RadialScanner& scanner);

  /// Adds the verification's evidence to the V-particles it names.
  void addEvidence(const std::vector<EvidenceBonus>& evidence);

  /// The hypotheses whose poses the following M-resamplings inject.
  void setLeading(std::vector<LeadingHypothesis> leading);

  /// V-resampling (paper 3.6, every w iterations): draws V-particles by their
  /// evidence, with the weight of each reported object's V-particles
  /// (`object_v_particles`, V indices) shared beyond a number per object.
  /// Returns the ancestry: for each new V-particle the index of the one it
  /// copies, or -1 when it was seeded afresh.
  std::vector<int> resampleV(const RadialScanner& scanner, const std::vector<std::vector<int>>& object_v_particles);

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
  int heldObjectAt(float x, float y) const;

  /// Moves the V-particles by the optical flow (one move per V-particle, in
  /// index order); a lost one is seeded afresh with new M-particles. Returns
  /// how many were lost.
  int applyFlow(const std::vector<VParticleMove>& moves, const RadialScanner& scanner);

  /// Moves every V-particle by an external displacement, kept inside the
  /// image; its M-particles stay where they are. InputError for a count
  /// other than the V-particles' or a displacement that is not finite.
  void displace(const std::vector<cv::Point2f>& displacement);

  const Params& params() const { return params_; }
  const PrototypeMemory& memory() const { return *memory_; }
  const std::vector<VParticle>& vParticles() const { return v_; }
  const MParticleSet& mParticles() const { return m_; }
  /// M-particle slots per V-particle (the budget): those of V-particle v
  /// start at v * mParticlesPerV().
  int mParticlesPerV() const { return static_cast<int>(prior_.slots().size()); }
  /// The M-particles V-particle v holds now: mParticlesPerV() of them, or
  /// fewer under KLD-sampling.
  MRange mRange(int v) const;
  /// Each V-particle's M-particles (index = V index).
  std::vector<MRange> mRanges() const;
  /// The mean number of M-particles per V-particle now.
  double meanMParticles() const;
  /// The proposal index, or null when index_share is 0.
  const ProposalIndex* proposalIndex() const { return index_.get(); }
  /// The places V-particle `v` is proposed seen frontally, best first: from
  /// the radial-profile index when it is on and the V-particle's profile
  /// can be read (the best aligned kProfileCandidates), else from the 8-ray
  /// index (`count` of them); empty without an index.
  std::vector<ProposalCandidate> frontalCandidates(const VParticle& v, const RadialScanner& scanner, int count) const;
  /// Frontal candidates kept from the radial-profile index.
  static constexpr int kProfileCandidates = 8;
  /// What the last memory's index build left out (a line per prototype).
  const std::vector<std::string>& indexWarnings() const { return index_warnings_; }
  /// The memory's look-alike pairs (discriminative_places.h), with their
  /// places when discriminative_moves and discriminative_places are on;
  /// null when competing_fits is 0 and the moves are off.
  const DiscriminativePlaces* lookAlikes() const { return places_.get(); }
  /// The prototype of each of a V-particle's M-particle slots at seeding.
  const std::vector<int>& priorSlots() const { return prior_.slots(); }
  /// The size of the image the filter was seeded on.
  const cv::Size& imageSize() const { return image_size_; }

private:
  /// What one V-particle slot's work draws from and writes besides its own
  /// particles: its random stream and its scratch.
  struct VWorkspace
  {
    explicit VWorkspace(Rng stream) : rng(stream) {}
    Rng rng;
    std::vector<ProposalCandidate> candidates;  // of the V-particle being seeded or updated
    std::vector<double> weights;
    std::vector<std::uint64_t> kld_bins;
  };

  /// Seeds V-particle `v` (a new pose and new M-particles in [begin, end)
  /// of `set`).
  void seedVAndM(VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end, const RadialScanner& scanner,
                 VWorkspace& work);
  void seedV(VParticle& v, const RadialScanner& scanner, Rng& rng);
  /// The prototype of a new M-particle whose prior slot is `slot`: with
  /// probability scene_prior_share (when objects are held) a held object's
  /// prototype, else `slot`.
  int scenePrototype(int slot, Rng& rng) const;
  /// The probability that a new M-particle is in prototype p: the context
  /// prior mixed with the held objects' prototypes (scenePrototype).
  double seedingProbability(int p) const;
  /// A uniform place in the image outside the held objects (inside one only
  /// when they cover the whole image).
  cv::Point2f drawFreePlace(Rng& rng) const;
  void seedMRange(MParticleSet& set, std::size_t begin, std::size_t end, const VParticle& v, VWorkspace& work) const;
  /// A new M-particle: with probability index_share (when the V-particle's
  /// query found places) at one of them, else uniformly in `prototype` as
  /// in the paper; with the importance weight of the mixture.
  void seedM(MParticleSet& set, std::size_t index, int prototype, const VParticle& v, VWorkspace& work) const;
  void seedUniform(MParticleSet& set, std::size_t index, int prototype, const VParticle& v, Rng& rng) const;
  void seedAtCandidate(MParticleSet& set, std::size_t index, const ProposalCandidate& c, Rng& rng) const;
  void clearMeasurement(MParticleSet& set, std::size_t index) const;
  /// log(seeding density / mixture density) at M-particle `index` of `set`.
  float logProposalWeight(const MParticleSet& set, std::size_t index, double share,
                          const std::vector<ProposalCandidate>& candidates) const;
  /// The places of the memory the V-particle's rays look like (into
  /// work.candidates): its own rays, and with oblique view shapes on, its
  /// rays read under one drawn view shape (particle_filter_proposals.cpp).
  void findCandidates(const VParticle& v, const RadialScanner& scanner, VWorkspace& work) const;
  /// KLD-sampling (Fox 2003): how many M-particles the next generation of
  /// a V-particle needs, given `picks` drawn from the current one.
  int kldCount(const std::vector<int>& picks, std::size_t begin, std::vector<std::uint64_t>& bins) const;
  /// Swaps `memory`'s parts with the filter's own (no reset): afterwards
  /// `memory` holds the replaced ones. ParameterError, before anything
  /// changes, when it was built for other parameters.
  void swapMemory(FilterMemory& memory);
  /// ray_correspondence affine: gives M-particle `index` a view shape,
  /// frontal or drawn (corrected_scan.h); true when it is not frontal.
  bool drawShape(MParticleSet& set, std::size_t index, Rng& rng) const;
  /// An oblique view shape: anisotropy log-uniform in [1, max_anisotropy]
  /// along a uniform axis.
  void drawObliqueShape(Rng& rng, float shape[3]) const;
  /// Scans the V-particle's rays (refreshing v.rays) and updates its
  /// M-particles by eqs. 5-6 (particle_filter_measurement.cpp).
  void measure(int v_index, const RadialScanner& scanner);
  void accumulateEvidence(int v_index);
  void resampleM(int v_index);
  /// Places M-particle `index` of m_scratch_ at the pose leading hypothesis
  /// `h` implies for V-particle `v`, with likelihood `worst`.
  void injectM(const VParticle& v, const LeadingHypothesis& h, std::size_t index, float worst, VWorkspace& work);
  std::vector<double> attentionWeights(const std::vector<std::vector<int>>& object_v_particles) const;
  /// The V-particles V-resampling carries over unchanged: of those on each
  /// held object (inside its hull or supporting it), the held_v_particles
  /// with the highest `log_weights`. Every V-particle on a held object gets
  /// log weight -inf (it is not drawn).
  std::vector<int> keepOnHeldObjects(std::vector<double>& log_weights) const;

  Params params_;
  std::shared_ptr<const PrototypeMemory> memory_;
  PrototypePrior prior_;
  std::unique_ptr<ExplorationPolicy> policy_;
  DiscriminativeMoveChooser discriminator_;  // used when params_.discriminative_moves
  ObservationModel observation_;
  MotionModel motion_;
  Rng rng_;                       // the V-resampling's draw
  std::vector<VWorkspace> work_;  // one per V-particle slot

  cv::Size image_size_;
  std::vector<VParticle> v_;
  MParticleSet m_;
  MParticleSet m_scratch_;
  std::vector<LeadingHypothesis> leading_;  // injected at the M-resamplings
  std::shared_ptr<const ProposalIndex> index_;  // null when index_share is 0
  std::shared_ptr<const ProfileIndex> profile_index_;  // null when index_share is 0 or profile_index is off
  std::shared_ptr<const DiscriminativePlaces> places_;  // lookAlikes()
  std::vector<std::string> index_warnings_;
  std::vector<int> m_count_;                   // M-particles each V-particle holds
  cv::Mat held_mask_;  // CV_16UC1 of image_size_: 0 free, k + 1 inside held object k's hull; empty: none held
  std::vector<std::vector<int>> held_v_;  // each held object's supporting V-particles (one entry per held object)
  std::vector<int> held_prototypes_;      // the held objects' prototypes whose prior is not 0
};
}  // namespace amcr
