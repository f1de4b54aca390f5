// Result extraction (spec "Output"): a function of what it reads of the
// particle filter (FilterReading), the scanned image and the tracks of the
// last frame. It
// returns the recognized objects and, explicitly, the feedback the filter
// takes from them: the verification's evidence per V-particle, the leading
// hypotheses to inject as M-particles, and the V-particles of each reported
// object (attention sharing at V-resampling).
#pragma once

#include <vector>

#include "amcr/extraction/object_extraction.h"
#include "amcr/extraction/recognition_result.h"
#include "amcr/extraction/rival_cache.h"
#include "amcr/extraction/track_registry.h"
#include "amcr/base/params.h"
#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/filter/resampler.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
class ParticleFilter;

/// What the filter takes from one extraction. The V indices refer to the
/// filter's V-particles at extraction time: they are to be used before the
/// next V-resampling (which replaces the V-particles) and not kept.
struct ExtractionFeedback
{
  /// Verification of converged V-particles' interpretations, in V order:
  /// before V-resampling, the filter adds them to the V-particles' evidence.
  std::vector<EvidenceBonus> evidence;
  /// The best verified hypotheses, reported or not: the M-resamplings of the
  /// next iteration inject their poses.
  std::vector<LeadingHypothesis> leading;
  /// For each reported object (same order as Extraction::objects), the V
  /// indices of the V-particles that support it.
  std::vector<std::vector<int>> object_v_particles;
  /// Places of the image's coverage lattice whose votes started a fit that
  /// could lead (coverage_schedule.h), best fit first: the next V-resampling
  /// seeds V-particles there, which the leading hypotheses' injection meets.
  std::vector<RayPlace> seed_places;
};

struct Extraction
{
  /// Each V-particle's dominant cluster (index = V index).
  std::vector<VParticleCluster> clusters;
  /// The objects at or above the decision threshold, best score first
  /// (track ids not assigned yet).
  std::vector<RecognizedObject> objects;
  /// Every object the extraction fitted and verified on the image, reported
  /// or not, best score first: what a diagnosis of a miss reads (the
  /// benchmark's recall funnel), never fed back.
  std::vector<RecognizedObject> verified;
  /// New objects that passed every check but were not reported: max_objects
  /// tracks were kept already.
  int over_limit = 0;
  ExtractionFeedback feedback;
};

/// What the extraction reads of the particle filter after an iteration,
/// and nothing else of it.
struct FilterReading
{
  const std::vector<VParticle>& v_particles;
  /// Each V-particle's dominant cluster (index = V index), as the extraction defines it.
  std::vector<VParticleCluster> clusters;
  const PrototypeMemory& memory;
  const DiscriminativePlaces* look_alikes;  ///< the memory's look-alike pairs; null: none
  const ProposalIndex* index = nullptr;     ///< the memory's proposal index (pose votes); null: none
};

/// What the extraction may use besides the filter.
struct ExtractionAids
{
  /// The frame's places of the coverage lattice (coverage_schedule.h): they
  /// vote for poses besides the V-particles when pose_vote_fits is on.
  std::vector<RayPlace> image_places;
  /// The generic rivals kept from frame to frame (rival_cache.h); null:
  /// fitted for this frame alone.
  RivalCache* rivals = nullptr;
};

/// The dominant cluster of each of the filter's V-particles (index = V index),
/// as the extraction defines it.
std::vector<VParticleCluster> filterClusters(const ParticleFilter& filter);
/// What the extraction reads of `filter` now (valid until it changes).
FilterReading readFilter(const ParticleFilter& filter);

/// Clusters, groups of agreeing V-particles, each group's and each track's
/// affine refined on the image's edges and verified against it, and the
/// report with its hysteresis for tracked objects (spec "Output", "Tracking").
/// Lengths in `params` are px of the scanned image (the recognizer's working
/// image), min_object_size included; `observation` bounds the fits' scale
/// (max_affine_scale) and the views a new object is reported at
/// (max_anisotropy: the filter proposes none beyond, and beyond it an affine
/// stretches a simple outline onto clutter's blobs); `num_threads`
/// (RunParams) is their threads.
Extraction extractObjects(FilterReading filter, const RadialScanner& scanner, const TrackRegistry& tracks,
                          const ExtractionParams& params, const ObservationParams& observation, int num_threads,
                          const ExtractionAids& aids = {});
}  // namespace amcr
