// Result extraction (spec "Output"): from clusters and groups to objects
// fitted and verified on the image, and the feedback the verification gives
// to attention (V-resampling) and to the M-particles (injection).
#include "amcr/extraction/object_extractor.h"

#include <algorithm>
#include <cmath>

#include "amcr/base/parallel_for.h"
#include "amcr/extraction/differing_parts.h"
#include "amcr/extraction/outline_edges.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/perspective_choice.h"
#include "amcr/extraction/viewing_angle.h"
#include "amcr/filter/discriminative_attention.h"
#include "amcr/filter/discriminative_places.h"

namespace amcr
{
namespace
{
constexpr int kMaxLeadingHypotheses = 3;           // hypotheses whose poses are injected as M-particles
constexpr std::size_t kMaxVerifiedHypotheses = 8;  // groups checked against the image per iteration
constexpr double kKeepTrackRatio = 0.65;           // a tracked object stays at this share of the decision threshold
constexpr double kTrackDistance = 40.0;            // px an object's centre may move between frames and keep its track
constexpr double kVerificationGain = 4.0;          // log-weight per unit of outline score above 0.5 (V-resampling)
// Outlines overlapping more are one object: the better is kept. Below a half
// (an elongated part found twice, slid along its axis, overlaps itself by a
// third); touching copies overlap by next to nothing.
constexpr double kSameObjectOverlap = 0.3;
constexpr double kLeadingScoreRatio = 0.5;         // a leading hypothesis scores at least this share of the threshold
constexpr std::size_t kMaxPerspectiveFits = 3;     // best candidates per frame that may get a homography
// Look-alikes (adoptSupport): outline points farther apart than this many
// score tolerances differ; a differing part of fewer points does not count;
// the edge support of one's differing part must beat the other's by the margin.
constexpr double kDifferingApart = 2.0;
constexpr int kMinDifferingPoints = 6;
constexpr double kDifferingPartsMargin = 0.25;
// A look-alike that verifies clearly (kClearWholeScore) and this much better
// on the whole outline wins whatever its differing part shows: a part of a
// few dozen points is read less surely than the whole, and one that
// verifies short of the decision threshold there while the whole verifies
// at 0.99 is still the better fit (one bird's other pose, on `similar`).
// Blobs of clutter, which a look-alike may fit a little better than the
// prototype they were taken for, rarely verify that well.
constexpr double kClearWholeMargin = 0.1;
constexpr double kClearWholeScore = 0.9;

/// An object verified on the image, with the V-particles that support it.
struct Candidate
{
  RecognizedObject object;
  std::vector<int> v_particles;  // V indices, one per correspondence
  Affine table_to_image;         // the fitted affine, table px -> input px
  double score_tolerance = 0.0;  // px: the score's tolerance at the object's size
  bool adopted = false;          // took over a look-alike's V-particles (adoptSupport)
};

/// Where the fit of one prototype starts: a group's affine and the affines
/// of the previous frame's objects near it (table -> image).
struct FitStart
{
  int prototype;
  std::vector<Affine> affines;
};

/// What every step of the extraction reads.
struct ExtractionInput
{
  const ParticleFilter& filter;
  const RadialScanner& scanner;
  const std::vector<VParticleCluster>& clusters;
  const Params& params;
  const PrototypeMemory& memory;
};

/// A candidate for a prototype at a table -> image affine (score, support,
/// correspondences, outline); false when the affine is out of bounds or the
/// object too small. With a `perspective` whose homography is used, the
/// outline, the score and the correspondences follow the homography.
bool describeObject(const ExtractionInput& in, int prototype, const Affine& table_to_image, Candidate& candidate,
                    const PerspectiveFit* perspective = nullptr)
{
  const Prototype& p = in.memory[prototype];
  double smallest = 0, largest = 0;
  affineScales(table_to_image, smallest, largest);
  Affine image_to_table;
  if (largest > in.params.max_affine_scale || smallest < 1.0 / in.params.max_affine_scale ||
      !invertAffine(table_to_image, image_to_table))
    return false;
  const bool use_homography = perspective != nullptr && perspective->used;
  const auto toImage = [&](const cv::Point2d& q) {
    return use_homography ? applyHomography(perspective->table_to_image, q) : applyAffine(table_to_image, q);
  };
  candidate = Candidate();
  candidate.table_to_image = table_to_image;
  RecognizedObject& object = candidate.object;
  object.label = p.label();
  object.instance = p.instance();
  object.prototype_id = prototype;
  for (const auto& o : p.outline())
    object.outline.push_back(toImage(cv::Point2d(o.position)));
  // Too small to tell shapes apart: neither reported nor fed back to attention.
  const double size = outlineSize(object.outline);
  if (size < in.params.min_object_size)
    return false;
  candidate.score_tolerance = verifyTolerance(size, in.params.verify_tolerance, in.params.verify_relative_tolerance);
  object.score = use_homography ? perspective->support
                                : outlineSupport(p, in.scanner, table_to_image, candidate.score_tolerance);
  object.prototype_to_image = composeAffine(p.originalToTable(), table_to_image);
  object.image_to_prototype = composeAffine(image_to_table, p.tableToOriginal());
  object.homography_valid = use_homography;
  object.homography = use_homography ? composeHomography(liftAffine(p.originalToTable()), perspective->table_to_image)
                                     : liftAffine(object.prototype_to_image);
  object.anisotropy = affineAnisotropy(object.prototype_to_image);
  object.viewing_angle_deg = viewingAngleDegrees(object.anisotropy);
  // Support: the converged V-particles whose cluster this transform explains.
  const std::vector<VParticle>& v = in.filter.vParticles();
  for (const VParticleCluster& c : in.clusters)
  {
    if (c.prototype != prototype || !isConverged(c, in.params.cluster_min_share))
      continue;
    const cv::Point2d image_point(v[c.v].x, v[c.v].y);
    const cv::Point2d predicted = toImage(cv::Point2d(c.mean));
    if (!(std::hypot(predicted.x - image_point.x, predicted.y - image_point.y) <= in.params.group_tolerance))
      continue;
    object.correspondences.push_back({image_point, applyAffine(p.tableToOriginal(), cv::Point2d(c.mean))});
    candidate.v_particles.push_back(c.v);
  }
  object.support = static_cast<int>(object.correspondences.size());
  return true;
}

/// The fit of the candidate's outline by a homography, when the outline
/// demands it (perspective_choice.h); the candidate is left as it is otherwise.
void fitPerspective(const ExtractionInput& in, Candidate& candidate)
{
  // Only an object that could be reported (as a tracked one) is worth it.
  if (!in.params.fit_homography || candidate.object.score < kKeepTrackRatio * in.params.decision_threshold)
    return;
  const int prototype = candidate.object.prototype_id;
  PerspectiveRule rule;
  rule.tolerance = candidate.score_tolerance;
  rule.max_scale = in.params.max_affine_scale;
  const PerspectiveFit fit = choosePerspective(in.memory[prototype], in.scanner, candidate.table_to_image,
                                               candidate.object.score, in.params.refine_iterations,
                                               in.params.refine_search, rule);
  Candidate perspective;
  if (fit.used && describeObject(in, prototype, candidate.table_to_image, perspective, &fit))
    candidate = std::move(perspective);
}

/// Whether a start of `prototype` begins near `centre` (image px).
bool startedNear(const ExtractionInput& in, const std::vector<FitStart>& starts, int prototype,
                 const cv::Point2d& centre)
{
  const cv::Point2d table_centre = in.memory[prototype].centre();
  for (const FitStart& start : starts)
  {
    if (start.prototype != prototype)
      continue;
    for (const Affine& affine : start.affines)
    {
      const cv::Point2d c = applyAffine(affine, table_centre);
      if (std::hypot(c.x - centre.x, c.y - centre.y) <= kTrackDistance)
        return true;
    }
  }
  return false;
}

/// The look-alikes of each tracked object's prototype (discriminative_places.h),
/// where the pair's alignment puts them on the object (b's table -> a's
/// table -> image), the least well verified object first.
std::vector<FitStart> lookAlikeStarts(const ExtractionInput& in, const std::vector<Track>& tracks,
                                      const std::vector<Affine>& track_affines)
{
  std::vector<FitStart> starts;
  const DiscriminativePlaces* alike = in.filter.lookAlikes();
  if (!alike)
    return starts;
  std::vector<std::size_t> by_score(tracks.size());
  for (std::size_t k = 0; k < by_score.size(); ++k)
    by_score[k] = k;
  std::stable_sort(by_score.begin(), by_score.end(), [&tracks](std::size_t i, std::size_t j) {
    return tracks[i].object.score < tracks[j].object.score;
  });
  for (std::size_t k : by_score)
    for (const AlikePair* pair : alike->lookAlikesOf(tracks[k].object.prototype_id))
    {
      Affine b_to_a;
      if (invertAffine(pair->a_to_b, b_to_a))
        starts.push_back({pair->b, {composeAffine(b_to_a, track_affines[k])}});
    }
  return starts;
}

// The other interpretations V-particles are still deciding between
// (discriminative_attention.h): each gets a fit of its own where no start
// of its prototype is near, the largest clusters first, so that of alike
// shapes at one place the image's outline decides (report() keeps the better
// of overlapping objects, and a better one leads the injection). Then the
// look-alikes of each tracked object's prototype (discriminative_places.h),
// where the pair's alignment puts them on the object, the least well
// verified object first: once a track's V-particles have converged on one
// of two prototypes the index confuses, no cluster of the other is left to
// compete, and a wrong one would be held for good.
void addCompetingStarts(const ExtractionInput& in, const std::vector<Track>& tracks,
                        const std::vector<Affine>& track_affines, std::vector<FitStart>& starts)
{
  if (in.params.competing_fits <= 0)
    return;
  struct Alternative
  {
    float share;
    FitStart start;
  };
  std::vector<Alternative> alternatives;
  // A look-alike of the V-particle's most likely interpretation: another
  // prototype (another place of the same one is no alternative at this place).
  for (const VParticle& v : in.filter.vParticles())
    for (int k = 1; k < v.competing.count; ++k)
    {
      const CompetingHypothesis& h = v.competing.hypothesis[k];
      Affine table_to_image;
      if (h.prototype == v.competing.hypothesis[0].prototype || !hypothesisTableToImage(h, table_to_image))
        continue;
      alternatives.push_back({h.share, {h.prototype, {table_to_image}}});
    }
  std::stable_sort(alternatives.begin(), alternatives.end(),
                   [](const Alternative& a, const Alternative& b) { return a.share > b.share; });
  for (FitStart& start : lookAlikeStarts(in, tracks, track_affines))
    alternatives.push_back({0.f, std::move(start)});
  int added = 0;
  for (Alternative& a : alternatives)
  {
    if (added >= in.params.competing_fits)
      break;
    const cv::Point2d centre = applyAffine(a.start.affines[0], in.memory[a.start.prototype].centre());
    if (startedNear(in, starts, a.start.prototype, centre))
      continue;
    starts.push_back(std::move(a.start));
    ++added;
  }
}

// Starting points of the fit: each group's affine, and each object of the
// previous frame (recognition and tracking run together: a pose, once
// fitted, is moved by the flow and refined on, not found again). A group near
// a previous object of its prototype tries both and keeps the better fit.
// Groups on held objects, which their tracks already start from, come last
// in the verification's limit, so that the unexplained ones get it.
std::vector<FitStart> fitStarts(const ExtractionInput& in, const TrackRegistry& registry)
{
  // Every group is verified, even a single V-particle's: one that passes
  // seeds the others through injection before it has the support to be reported.
  std::vector<ObjectHypothesis> hypotheses = groupClusters(in.filter.vParticles(), in.clusters, in.params, 1);
  const std::vector<Track>& tracks = registry.tracks();
  std::vector<Affine> track_affines;  // each track's table -> image affine, moved by the flow
  for (const Track& t : tracks)
    track_affines.push_back(
        composeAffine(in.memory[t.object.prototype_id].tableToOriginal(), t.object.prototype_to_image));
  // Each group with the tracks of its prototype whose centre is near its own.
  struct GroupStart
  {
    const ObjectHypothesis* group;
    std::vector<std::size_t> near;
    bool on_held = false;
  };
  std::vector<GroupStart> groups;
  for (const ObjectHypothesis& h : hypotheses)
  {
    GroupStart g{&h, {}};
    const cv::Point2d centre = applyAffine(h.table_to_image, in.memory[h.prototype].centre());
    for (std::size_t k = 0; k < tracks.size(); ++k)
    {
      const cv::Point2d track_centre = applyAffine(track_affines[k], in.memory[h.prototype].centre());
      if (tracks[k].object.prototype_id == h.prototype &&
          std::hypot(centre.x - track_centre.x, centre.y - track_centre.y) <= kTrackDistance)
      {
        g.near.push_back(k);
        g.on_held = g.on_held || tracks[k].object.state == ObjectState::kHeld;
      }
    }
    groups.push_back(std::move(g));
  }
  std::stable_partition(groups.begin(), groups.end(), [](const GroupStart& g) { return !g.on_held; });
  if (groups.size() > kMaxVerifiedHypotheses)
    groups.resize(kMaxVerifiedHypotheses);

  std::vector<FitStart> starts;
  std::vector<bool> track_used(tracks.size(), false);
  for (const GroupStart& g : groups)
  {
    FitStart start{g.group->prototype, {g.group->table_to_image}};
    for (std::size_t k : g.near)
    {
      start.affines.push_back(track_affines[k]);
      track_used[k] = true;
    }
    starts.push_back(std::move(start));
  }
  for (std::size_t k = 0; k < tracks.size(); ++k)
    if (!track_used[k])
      starts.push_back({tracks[k].object.prototype_id, {track_affines[k]}});
  addCompetingStarts(in, tracks, track_affines, starts);
  return starts;
}

/// Each start refined on the image's edges and verified; of a start's
/// affines the best fit. Best score first (stable). The starts are fitted
/// in parallel (params.num_threads), each into its own slot, and kept in
/// their order: the same candidates whatever the thread count.
std::vector<Candidate> fitCandidates(const ExtractionInput& in, const std::vector<FitStart>& starts)
{
  const int threads = resolveThreads(in.params.num_threads);
  std::vector<Candidate> fitted(starts.size());
  std::vector<char> found(starts.size(), 0);
  parallelFor(static_cast<int>(starts.size()), threads, [&](int s) {
    const FitStart& start = starts[s];
    const Prototype& p = in.memory[start.prototype];
    for (const Affine& affine : start.affines)
    {
      Candidate candidate;
      const Affine refined = refineOnEdges(p, in.scanner, affine, in.params.refine_iterations, in.params.refine_search);
      if (describeObject(in, start.prototype, refined, candidate) &&
          (!found[s] || candidate.object.score > fitted[s].object.score))
      {
        fitted[s] = std::move(candidate);
        found[s] = 1;
      }
    }
  });
  std::vector<Candidate> candidates;
  for (std::size_t s = 0; s < starts.size(); ++s)
    if (found[s])
      candidates.push_back(std::move(fitted[s]));
  const auto byScore = [](const Candidate& a, const Candidate& b) { return a.object.score > b.object.score; };
  std::stable_sort(candidates.begin(), candidates.end(), byScore);
  // The homography, for the best few that could be reported (its fit costs
  // about as much as the rest of the extraction).
  parallelFor(static_cast<int>(std::min(candidates.size(), kMaxPerspectiveFits)), threads,
              [&](int i) { fitPerspective(in, candidates[i]); });
  std::stable_sort(candidates.begin(), candidates.end(), byScore);
  return candidates;
}

// Attention feedback from the verification: a converged V-particle whose
// interpretation the whole outline confirms gains V-weight, one whose
// interpretation the image contradicts loses it (the paper's V-weight,
// "V-particles on clutter die out", made explicit).
std::vector<EvidenceBonus> verificationEvidence(const ExtractionInput& in, const std::vector<Candidate>& candidates)
{
  std::vector<EvidenceBonus> evidence;
  const std::vector<VParticle>& v = in.filter.vParticles();
  for (const VParticleCluster& c : in.clusters)
  {
    if (!isConverged(c, in.params.cluster_min_share))
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
      if (std::hypot(predicted.x - v[c.v].x, predicted.y - v[c.v].y) <= in.params.group_tolerance)
        best = object.score;
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

/// Whether `better` verifies clearly and kClearWholeMargin better than
/// `supported` on the whole outline.
bool clearlyBetterOnTheWhole(const Candidate& better, const Candidate& supported)
{
  return better.object.score >= kClearWholeScore && better.object.score - supported.object.score >= kClearWholeMargin;
}

/// Whether `better`, which verifies at least as well as `supported` on the
/// whole outline, also does on the parts where the two outlines differ
/// (differing_parts.h): its own differing part verifies as an object must
/// (decision_threshold) and by kDifferingPartsMargin better than the other's.
bool winsOnDifferingParts(const ExtractionInput& in, const Candidate& better, const Candidate& supported)
{
  const double tolerance = std::max(better.score_tolerance, supported.score_tolerance);
  const DifferingParts parts = compareDifferingParts(
      in.scanner, mapOutline(in.memory[better.object.prototype_id], better.table_to_image),
      mapOutline(in.memory[supported.object.prototype_id], supported.table_to_image), tolerance,
      kDifferingApart * tolerance);
  // Its own differing part must be there on the image, as a whole outline
  // must be to be reported; the other's, where too small to count, is neutral.
  if (parts.a_points < kMinDifferingPoints || parts.a_support < in.params.decision_threshold)
    return false;
  const double supported_part = parts.b_points >= kMinDifferingPoints ? parts.b_support : 0.5;
  return parts.a_support - supported_part > kDifferingPartsMargin;
}

// Of alike shapes at one place the image decides where they differ, not the
// count of V-particles: the M-particles of the V-particles on an object can
// settle in a look-alike prototype (a bird in another pose, or without its
// crest) while a competing cluster's fit (addCompetingStarts) verifies
// better. A candidate that overlaps a better supported one of another
// prototype, verifies at least as well on the whole outline and clearly
// better on the parts where the two differ (or clearly better on the whole),
// takes over its V-particles as support, each with the correspondence its
// own transform gives; report() then suppresses the other.
void adoptSupport(const ExtractionInput& in, std::vector<Candidate>& candidates)
{
  const std::vector<VParticle>& v = in.filter.vParticles();
  for (std::size_t i = 0; i < candidates.size(); ++i)
  {
    Candidate& better = candidates[i];
    for (std::size_t j = i + 1; j < candidates.size(); ++j)  // best score first: j scores no more than i
    {
      const Candidate& supported = candidates[j];
      if (supported.object.prototype_id == better.object.prototype_id ||
          supported.object.support <= better.object.support ||
          better.object.score < in.params.decision_threshold ||
          outlineOverlap(better.object.outline, supported.object.outline) <= kSameObjectOverlap ||
          !(clearlyBetterOnTheWhole(better, supported) || winsOnDifferingParts(in, better, supported)))
        continue;
      RecognizedObject& object = better.object;
      object.correspondences.clear();
      better.v_particles = supported.v_particles;
      for (int k : better.v_particles)
      {
        const cv::Point2d image_point(v[k].x, v[k].y);
        object.correspondences.push_back({image_point, applyAffine(object.image_to_prototype, image_point)});
      }
      object.support = static_cast<int>(object.correspondences.size());
      better.adopted = true;
    }
  }
}

/// Reports what passes the decision threshold; of two overlapping objects
/// the better one; a new object only while the registry has room (max_objects).
void report(const Params& params, const TrackRegistry& registry, std::vector<Candidate>& candidates,
            Extraction& extraction)
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
    if (c.score < threshold || c.support < support || (!track && !registry.hasRoom(new_tracks)))
      continue;
    bool suppressed = false;
    for (const auto& kept : extraction.objects)
      suppressed = suppressed || outlineOverlap(c.outline, kept.outline) > kSameObjectOverlap;
    if (suppressed)
      continue;
    new_tracks += track ? 0 : 1;
    extraction.objects.push_back(std::move(candidate.object));
    extraction.feedback.object_v_particles.push_back(std::move(candidate.v_particles));
  }
}
}  // namespace

std::vector<VParticleCluster> filterClusters(const ParticleFilter& filter)
{
  return dominantClusters(filter.vParticles(), filter.mParticles(), filter.mRanges(),
                          static_cast<int>(filter.memory().size()), filter.params().cluster_radius);
}

Extraction extractObjects(const ParticleFilter& filter, const RadialScanner& scanner, const TrackRegistry& tracks)
{
  return extractObjects(filter, scanner, tracks, filter.params().min_object_size);
}

Extraction extractObjects(const ParticleFilter& filter, const RadialScanner& scanner, const TrackRegistry& tracks,
                          double min_object_size)
{
  Extraction extraction;
  extraction.clusters = filterClusters(filter);
  Params params = filter.params();
  params.min_object_size = min_object_size;
  const ExtractionInput in{filter, scanner, extraction.clusters, params, filter.memory()};
  std::vector<Candidate> candidates = fitCandidates(in, fitStarts(in, tracks));
  if (in.params.competing_fits > 0)
    adoptSupport(in, candidates);
  extraction.feedback.evidence = verificationEvidence(in, candidates);
  extraction.feedback.leading = leadingHypotheses(in, candidates);
  for (const Candidate& candidate : candidates)
    extraction.verified.push_back(candidate.object);
  report(in.params, tracks, candidates, extraction);
  return extraction;
}
}  // namespace amcr
