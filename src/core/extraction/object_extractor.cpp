// Result extraction (spec "Output"): from clusters and groups to objects
// fitted and verified on the image, and the feedback the verification gives
// to attention (V-resampling) and to the M-particles (injection). The steps
// before the feedback are in fit_starts.cpp, candidate_fit.cpp and
// look_alike_support.cpp (extraction_steps.h).
#include "amcr/extraction/object_extractor.h"

#include <algorithm>
#include <cmath>

#include "amcr/extraction/track_registry.h"
#include "amcr/filter/particle_filter.h"
#include "extraction_steps.h"

namespace amcr
{
using namespace extraction_steps;  // the steps and what they share (extraction_steps.h)

namespace
{
constexpr int kMaxLeadingHypotheses = 3;           // hypotheses whose poses are injected as M-particles
constexpr double kVerificationGain = 4.0;          // log-weight per unit of outline score above 0.5 (V-resampling)
constexpr std::size_t kMaxSeedPlaces = 12;         // places of the image's candidates V-resampling seeds at

// Attention feedback from the verification: a converged V-particle whose
// interpretation the whole outline confirms gains V-weight, one whose
// interpretation the image contradicts loses it (the paper's V-weight,
// "V-particles on clutter die out", made explicit).
std::vector<EvidenceBonus> verificationEvidence(const ExtractionInput& in, const std::vector<Candidate>& candidates)
{
  std::vector<EvidenceBonus> evidence;
  const std::vector<VParticle>& v = in.v_particles;
  for (const VParticleCluster& c : in.clusters)
  {
    if (!c.converged)
      continue;
    double best = -1.0;
    for (const Candidate& candidate : candidates)
    {
      const RecognizedObject& object = candidate.object;
      if (object.prototype_id != c.prototype || object.score <= best)
        continue;
      const Prototype& p = in.memory[c.prototype];
      const cv::Point2d prototype_point = applyAffine(p.tableToOriginal(), cv::Point2d(c.mean));
      const cv::Point2d predicted = object.homography_valid ? applyHomography(object.homography, prototype_point)
                                                            : applyAffine(object.prototype_to_image, prototype_point);
      // One whose distinguishing parts are not on edges is no better than
      // its generic rival: its V-particles gain nothing from it.
      if (std::hypot(predicted.x - v[c.v].x, predicted.y - v[c.v].y) <= in.params.group_tolerance)
        best = passesRivals(in.params, candidate, true) ? object.score : std::min(object.score, 0.5);
    }
    if (best >= 0.0)
      evidence.push_back({c.v, kVerificationGain * (best - 0.5)});
  }
  return evidence;
}

/// The leading hypotheses seed M-particles at the next iteration, reported or not.
std::vector<LeadingHypothesis> leadingHypotheses(const ExtractionInput& in, const std::vector<Candidate>& candidates)
{
  std::vector<LeadingHypothesis> leading;
  for (const auto& candidate : candidates)
  {
    const RecognizedObject& c = candidate.object;
    if (static_cast<int>(leading.size()) >= kMaxLeadingHypotheses ||
        c.score < kLeadingScoreRatio * in.params.decision_threshold)
      break;
    const Prototype& p = in.memory[c.prototype_id];
    leading.push_back({c.prototype_id, composeAffine(c.image_to_prototype, p.originalToTable())});
  }
  return leading;
}

/// The coverage lattice's places that voted for a fit that could lead, best
/// fit first, outside tracked objects (their V-particles are there already).
std::vector<RayPlace> seedPlaces(const ExtractionInput& in, const TrackRegistry& registry,
                                 const std::vector<Candidate>& candidates)
{
  std::vector<RayPlace> places;
  for (const Candidate& candidate : candidates)
  {
    if (candidate.object.score < kLeadingScoreRatio * in.params.decision_threshold)
      break;
    if (registry.continued(candidate.object))
      continue;
    for (const RayPlace& place : candidate.image_places)
      if (places.size() < kMaxSeedPlaces)
        places.push_back(place);
  }
  return places;
}

/// Reports what passes the decision threshold; of two overlapping objects
/// the better one; a new object only while the registry has room
/// (max_objects), counting those it had none for, and only when seen within
/// `max_anisotropy` (a tracked one may turn further).
void report(const ExtractionParams& params, double max_anisotropy, const TrackRegistry& registry,
            std::vector<Candidate>& candidates, Extraction& extraction)
{
  int new_tracks = 0;
  for (auto& candidate : candidates)
  {
    const RecognizedObject& c = candidate.object;
    // Hysteresis: an object of the previous frames stays while its score
    // keeps above a share of the threshold; one V-particle must support it
    // while it is tentative; once confirmed, the tracker and the edges
    // follow it alone.
    const Track* track = registry.continued(c);
    const double threshold = params.decision_threshold * (track ? kKeepTrackRatio : 1.0);
    // One that took over a look-alike's V-particles needs one of them: the
    // look-alike had min_support when it was found, and a held object keeps
    // only held_v_particles.
    int support = candidate.adopted ? 1 : params.min_support;
    if (track)
      support = track->object.state == ObjectState::kTentative ? 1 : 0;
    // A new object must explain its distinguishing parts (generic_rivals.h).
    // A tracked one passed that check when it started; it keeps its track
    // while they drop below the check's hysteresis for a few frames (a moving
    // part blurs them for a while), not for kRivalGraceFrames in a row.
    const bool rivals = track ? (passesRivals(params, candidate, true) || track->rival_misses < kRivalGraceFrames)
                              : passesRivals(params, candidate, false);
    // Enough of it must show: the score is of the visible outline alone.
    const bool visible = c.visible_share >= params.min_visible_share * (track ? kKeepTrackRatio : 1.0);
    if (c.score < threshold || c.support < support || !rivals || !visible ||
        (!track && c.anisotropy > max_anisotropy))
      continue;
    bool suppressed = false;
    for (const auto& kept : extraction.objects)
      suppressed = suppressed || outlineOverlap(c.outline, kept.outline) > kSameObjectOverlap;
    if (suppressed)
      continue;
    if (!track && !registry.hasRoom(new_tracks))
    {
      ++extraction.over_limit;  // said, not dropped in silence (RecognitionResult::objects_over_limit)
      continue;
    }
    new_tracks += track ? 0 : 1;
    extraction.objects.push_back(std::move(candidate.object));
    extraction.feedback.object_v_particles.push_back(std::move(candidate.v_particles));
  }
}
}  // namespace

std::vector<VParticleCluster> filterClusters(const ParticleFilter& filter)
{
  return dominantClusters(filter.vParticles(), filter.mParticles(), filter.mRanges(),
                          static_cast<int>(filter.memory().size()), filter.params());
}

FilterReading readFilter(const ParticleFilter& filter)
{
  return FilterReading{filter.vParticles(), filterClusters(filter), filter.memory(), filter.lookAlikes(),
                       filter.proposalIndex()};
}

Extraction extractObjects(FilterReading filter, const RadialScanner& scanner, const TrackRegistry& tracks,
                          const ExtractionParams& params, const ObservationParams& observation, int num_threads,
                          const ExtractionAids& aids)
{
  Extraction extraction;
  extraction.clusters = std::move(filter.clusters);
  const std::vector<VParticle>& v = filter.v_particles;
  ExtractionInput plain{v, extraction.clusters, filter.look_alikes, scanner, params, filter.memory,
                        observation.max_affine_scale, num_threads};
  plain.index = filter.index;
  plain.image_places = &aids.image_places;
  const std::vector<FitStart> starts = fitStarts(plain, tracks);
  // The generic rivals of the prototypes fitted in this frame, once each.
  RivalCache frame_rivals;
  RivalCache& rivals = aids.rivals ? *aids.rivals : frame_rivals;
  fitRivals(plain, starts, rivals);
  ExtractionInput in = plain;
  in.rivals = &rivals;
  std::vector<Candidate> candidates = fitCandidates(in, starts);
  verifyRivals(in, candidates);
  if (in.params.competing_fits > 0)
    adoptSupport(in, candidates);
  extraction.feedback.evidence = verificationEvidence(in, candidates);
  extraction.feedback.leading = leadingHypotheses(in, candidates);
  extraction.feedback.seed_places = seedPlaces(in, tracks, candidates);
  for (const Candidate& candidate : candidates)
    extraction.verified.push_back(candidate.object);
  report(in.params, observation.max_anisotropy, tracks, candidates, extraction);
  return extraction;
}
}  // namespace amcr
