// Where the fits of the result extraction start: each group's affine, each
// tracked object moved by the flow, and the interpretations V-particles are
// still deciding between, with the look-alikes of each tracked prototype.
#include <algorithm>
#include <cmath>
#include <utility>

#include <opencv2/imgproc.hpp>

#include "amcr/filter/discriminative_attention.h"
#include "amcr/extraction/outline_edges.h"
#include "amcr/extraction/pose_votes.h"
#include "amcr/filter/discriminative_places.h"
#include "extraction_steps.h"

namespace amcr
{
namespace extraction_steps
{
namespace
{
constexpr std::size_t kMaxVerifiedHypotheses = 8;  // groups checked against the image per iteration
constexpr double kTrackDistance = 40.0;            // px an object's centre may move between frames and keep its track
constexpr int kVotesPerPlace = 3;                   // the index's nearest matches each V-particle's rays vote for

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
  const DiscriminativePlaces* alike = in.look_alikes;
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
        starts.push_back({pair->b, {composeAffine(b_to_a, track_affines[k])}, false, {}, {}});
    }
  return starts;
}

/// Whether V-particle `v` lies inside one of `outlines` (the tracked objects'
/// in the previous frame's pose: the flow moved both alike).
bool insideAny(const std::vector<std::vector<cv::Point2f>>& outlines, const VParticle& v)
{
  for (const std::vector<cv::Point2f>& outline : outlines)
    if (outline.size() >= 3 && cv::pointPolygonTest(outline, cv::Point2f(v.x, v.y), false) >= 0)
      return true;
  return false;
}

/// Whether `centre` (image px) lies within kTrackDistance of a tracked object's centre.
bool nearTrack(const ExtractionInput& in, const std::vector<Track>& tracks, const std::vector<Affine>& track_affines,
               const cv::Point2d& centre)
{
  for (std::size_t k = 0; k < tracks.size(); ++k)
  {
    const cv::Point2d c = applyAffine(track_affines[k], in.memory[tracks[k].object.prototype_id].centre());
    if (std::hypot(c.x - centre.x, c.y - centre.y) <= kTrackDistance)
      return true;
  }
  return false;
}

// The likeliest modes of the V-particles that have not converged, the most
// likely first (object_extraction.h): with many prototypes the likelihood
// of eq. 5 spreads a V-particle's M-particles over hypotheses that explain
// its rays almost as well as the truth, so its densest mode converges late
// or never, while its most likely one is often the truth already. A fit
// there is checked against the image as any other; one that could be
// reported leads the injection, which concentrates the M-particles on it.
// Not on a tracked object: its track starts there already, and the
// competing fits try its alternatives. Up to likeliest_fits per frame.
void addLikeliestStarts(const ExtractionInput& in, const std::vector<Track>& tracks,
                        const std::vector<Affine>& track_affines, std::vector<FitStart>& starts)
{
  std::vector<const VParticleCluster*> open;
  for (const VParticleCluster& c : in.clusters)
    if (!c.converged && c.likeliest.has_affine)
      open.push_back(&c);
  std::stable_sort(open.begin(), open.end(), [](const VParticleCluster* a, const VParticleCluster* b) {
    return a->likeliest.log_likelihood > b->likeliest.log_likelihood;
  });
  int added = 0;
  for (const VParticleCluster* c : open)
  {
    if (added >= in.params.likeliest_fits)
      break;
    Affine table_to_image;
    if (!invertAffine(c->likeliest.image_to_table, table_to_image))
      continue;
    const int prototype = c->likeliest.prototype;
    const cv::Point2d centre = applyAffine(table_to_image, in.memory[prototype].centre());
    if (nearTrack(in, tracks, track_affines, centre) || startedNear(in, starts, prototype, centre))
      continue;
    starts.push_back({prototype, {table_to_image}, false, {}, {}});
    ++added;
  }
}

// Poses the image proposes (pose_votes.h): the rays where each V-particle
// that has not converged stands, and at the frame's places of the coverage
// lattice (coverage_schedule.h), looked up in the proposal index, pooled by
// prototype and pose; the pools with most votes are fitted, up to
// pose_vote_fits per frame (V-particles on a tracked object do not vote, the
// lattice skips held objects; no pool near a tracked object or where a start
// of its prototype is).
void addVoteStarts(const ExtractionInput& in, const std::vector<Track>& tracks,
                   const std::vector<Affine>& track_affines, std::vector<FitStart>& starts)
{
  if (!in.index || in.params.pose_vote_fits <= 0)
    return;
  std::vector<std::vector<cv::Point2f>> outlines;
  for (const Track& t : tracks)
    outlines.emplace_back(t.object.outline.begin(), t.object.outline.end());
  std::vector<RayPlace> places;
  std::vector<int> place_v;  // the V-particle of each place; -1 for the lattice's
  for (const VParticleCluster& c : in.clusters)
    if (!c.converged && !insideAny(outlines, in.v_particles[c.v]))
    {
      places.push_back({in.v_particles[c.v].x, in.v_particles[c.v].y, in.v_particles[c.v].theta});
      place_v.push_back(c.v);
    }
  if (in.image_places)
    for (const RayPlace& place : *in.image_places)
    {
      places.push_back(place);
      place_v.push_back(-1);
    }
  // The fits go to the pools with most votes. Choosing pools by how well
  // their outline meets the image's edges as they stand was tried in turn
  // with the votes: it found more beside few prototypes, fewer beside 70,
  // and fitted shapes framed by clutter lines (docs/benchmark.md).
  const std::vector<PoseVote> pools = poolPoseVotes(*in.index, in.memory, in.scanner, places, kVotesPerPlace);
  int added = 0;
  for (const PoseVote& vote : pools)
  {
    if (added >= in.params.pose_vote_fits)
      break;
    const cv::Point2d centre = applyAffine(vote.table_to_image, in.memory[vote.prototype].centre());
    if (nearTrack(in, tracks, track_affines, centre) || startedNear(in, starts, vote.prototype, centre))
      continue;  // tracked, fitted already, or a pool of its prototype starts there
    FitStart start{vote.prototype, {vote.table_to_image}, false, {}, {}};
    for (int place : vote.places)
    {
      if (place_v[place] >= 0)
        start.voters.push_back(place_v[place]);
      else
        start.image_places.push_back(places[place]);
    }
    starts.push_back(std::move(start));
    ++added;
  }
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
  for (const VParticle& v : in.v_particles)
    for (int k = 1; k < v.competing.count; ++k)
    {
      const CompetingHypothesis& h = v.competing.hypothesis[k];
      Affine table_to_image;
      if (h.prototype == v.competing.hypothesis[0].prototype || !hypothesisTableToImage(h, table_to_image))
        continue;
      alternatives.push_back({h.share, {h.prototype, {table_to_image}, false, {}, {}}});
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
}  // namespace

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
  std::vector<ObjectHypothesis> hypotheses = groupClusters(in.v_particles, in.clusters, in.params, 1);
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
    FitStart start{g.group->prototype, {g.group->table_to_image}, !g.near.empty(), {}, {}};
    for (std::size_t k : g.near)
    {
      start.affines.push_back(track_affines[k]);
      track_used[k] = true;
    }
    starts.push_back(std::move(start));
  }
  for (std::size_t k = 0; k < tracks.size(); ++k)
    if (!track_used[k])
      starts.push_back({tracks[k].object.prototype_id, {track_affines[k]}, true, {}, {}});
  addLikeliestStarts(in, tracks, track_affines, starts);
  addVoteStarts(in, tracks, track_affines, starts);
  addCompetingStarts(in, tracks, track_affines, starts);
  return starts;
}
}  // namespace extraction_steps
}  // namespace amcr
