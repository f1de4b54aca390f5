// The steps of the result extraction (extractObjects, object_extractor.cpp)
// and what they share: where the fits start (fit_starts.cpp), the candidates
// fitted and verified on the image (candidate_fit.cpp), and the support a
// look-alike takes over (look_alike_support.cpp). Private to src/core.
#pragma once

#include <vector>

#include "amcr/base/affine.h"
#include "amcr/base/homography.h"
#include "amcr/base/params.h"
#include "amcr/extraction/generic_rivals.h"
#include "amcr/extraction/object_extraction.h"
#include "amcr/extraction/recognition_result.h"
#include "amcr/extraction/rival_cache.h"
#include "amcr/extraction/track_registry.h"
#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"
#include "report_rules.h"

namespace amcr
{
namespace extraction_steps
{
/// An object verified on the image, with the V-particles that support it.
struct Candidate
{
  RecognizedObject object;
  std::vector<int> v_particles;  // V indices, one per correspondence
  Affine table_to_image;         // the fitted affine, table px -> input px
  double score_tolerance = 0.0;  // px: the score's tolerance at the object's size
  bool adopted = false;          // took over a look-alike's V-particles (adoptSupport)
  bool rival_hidden = false;     // its distinguishing parts are mostly covered (RivalVerdict::hidden)
  std::vector<std::uint8_t> covered_found;  // OutlineVerification::covered_found of its fit
  std::vector<RayPlace> image_places;  // the image's places that voted for its start (coverage_schedule.h)
};

/// Where the fit of one prototype starts: a group's affine and the affines
/// of the previous frame's objects near it (table -> image).
struct FitStart
{
  int prototype;
  std::vector<Affine> affines;
  /// Whether a tracked object's pose is among the affines: its fit was
  /// chosen when the track started and is not tried at other turns.
  bool tracked = false;
  /// The V-particles whose rays voted for the start's pose (pose_votes.h).
  std::vector<int> voters;
  /// The places of the image's coverage lattice that voted for it (coverage_schedule.h).
  std::vector<RayPlace> image_places;
};


/// What every step of the extraction reads.
struct ExtractionInput
{
  const std::vector<VParticle>& v_particles;
  const std::vector<VParticleCluster>& clusters;  ///< each V-particle's dominant cluster
  const DiscriminativePlaces* look_alikes;         ///< the memory's look-alike pairs; null: none
  const RadialScanner& scanner;
  const ExtractionParams& params;
  const PrototypeMemory& memory;
  double max_affine_scale;             ///< of the observation model (ObservationParams): the fits' scale bound
  int num_threads;                     ///< RunParams::num_threads: the fits' and the rival checks' threads
  const RivalCache* rivals = nullptr;  ///< with the rivals of the frame's starts (fitRivals); none: fitted where needed
  const ProposalIndex* index = nullptr;  ///< the memory's proposal index (pose votes); none: no votes
  /// The frame's places of the coverage lattice (coverage_schedule.h), which vote besides the V-particles.
  const std::vector<RayPlace>* image_places = nullptr;
};

/// Where the fits start: each group of clusters, each tracked object, and
/// the competing interpretations (fit_starts.cpp).
std::vector<FitStart> fitStarts(const ExtractionInput& in, const TrackRegistry& registry);

/// Each start refined on the image's edges and verified, best score first
/// (candidate_fit.cpp).
std::vector<Candidate> fitCandidates(const ExtractionInput& in, const std::vector<FitStart>& starts);

/// The share of a candidate's distinguishing points (against its
/// prototype's generic rivals) on the image's edges, for every candidate
/// that could be reported (candidate_fit.cpp).
void verifyRivals(const ExtractionInput& in, std::vector<Candidate>& candidates);

/// Fits into `cache` the generic rivals of the starts' prototypes it does
/// not hold yet, when the rival check is on (rival_check.cpp).
void fitRivals(const ExtractionInput& in, const std::vector<FitStart>& starts, RivalCache& cache);

/// The rival check of prototype `prototype` (its index) at a table -> image
/// transform, with the distinguishing points' search scaled from the
/// score's tolerance; with `covered` (per outline point), the visible
/// distinguishing points only.
RivalVerdict rivalVerdict(const ExtractionInput& in, int prototype, const Homography& table_to_image,
                          double score_tolerance, const std::vector<std::uint8_t>& covered = {});

/// For a prototype whose rival ellipse explains its body but not its
/// distinguishing part at `table_to_image`: the pose turned about the
/// ellipse's centre (every 5 degrees when round, else half a turn) that
/// puts the distinguishing part best on edges, in `turned`; false when no
/// turn does better (rival_check.cpp).
bool turnOntoDistinguishingParts(const ExtractionInput& in, int prototype, const Affine& table_to_image,
                                 double score_tolerance, Affine& turned);

/// Whether a candidate passes its rival check: at least rival_part_support
/// of its distinguishing points on edges (`tracked`: kKeepTrackRatio of it).
bool passesRivals(const ExtractionParams& params, const Candidate& candidate, bool tracked);

/// A candidate that verifies better than an overlapping look-alike where
/// the two differ takes over its support (look_alike_support.cpp).
void adoptSupport(const ExtractionInput& in, std::vector<Candidate>& candidates);
}  // namespace extraction_steps
}  // namespace amcr
