#include "amcr/extraction/flow_tracker.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr std::size_t kOutlineFlowPoints = 32;  // outline points whose flow gives a track's motion
constexpr double kMinTrackInlierShare = 0.4;    // of those, the share that must agree on one motion
constexpr int kMinTrackInliers = 6;             // and at least this many: a similarity has 4 degrees of freedom
// A V-particle whose own flow fails moves as the nearest this many whose
// flow succeeded (the median of their displacements).
constexpr std::size_t kNeighbourFlows = 5;

/// Up to `count` points evenly spaced along `outline`.
std::vector<cv::Point2f> sampleOutline(const std::vector<cv::Point2d>& outline, std::size_t count)
{
  std::vector<cv::Point2f> points;
  const std::size_t step = std::max<std::size_t>(1, outline.size() / count);
  for (std::size_t i = 0; i < outline.size(); i += step)
    points.emplace_back(static_cast<float>(outline[i].x), static_cast<float>(outline[i].y));
  return points;
}

/// One track's motion between the frames and its outline in the previous one.
struct TrackMotion
{
  bool moved = false;
  Affine motion;
  std::vector<cv::Point2f> outline;
};

/// The track a point of the previous frame lies on (the first that moved), or -1.
int trackAt(const std::vector<TrackMotion>& motions, const cv::Point2f& point)
{
  for (std::size_t k = 0; k < motions.size(); ++k)
    if (motions[k].moved && cv::pointPolygonTest(motions[k].outline, point, false) >= 0)
      return static_cast<int>(k);
  return -1;
}

/// The move of a V-particle with the motion of its track (which also turns
/// its heading with the object, so its M-particles' headings stay right).
VParticleMove moveWithTrack(const VParticle& v, const Affine& m, const cv::Size& image_size)
{
  VParticleMove move;
  move.kind = VParticleMove::Kind::kWithTrack;
  const cv::Point2d to = applyAffine(m, cv::Point2d(v.x, v.y));
  move.x = static_cast<float>(std::min(std::max(to.x, 0.0), image_size.width - 1.0));
  move.y = static_cast<float>(std::min(std::max(to.y, 0.0), image_size.height - 1.0));
  move.theta = static_cast<float>(wrapAngle(v.theta + std::atan2(m(1, 0), m(0, 0))));
  return move;
}

/// The moves of the free V-particles for which Lucas-Kanade found no flow
/// at all. A point of an untextured surface (the inside of a flat part, a wall) has no flow of its
/// own: Lucas-Kanade's window sees no gradient, and in a clean image no
/// noise either. Such a V-particle moves as its nearest neighbours whose
/// flow succeeded (the median of their displacements) instead of being
/// seeded afresh every frame, which kept it from ever converging. Without
/// kNeighbourFlows successful flows in the frame it stays lost.
void moveWithNeighbours(const std::vector<cv::Point2f>& from, const std::vector<FlowVector>& flow,
                        const cv::Size& image_size, std::vector<VParticleMove>& moves, const std::vector<int>& index)
{
  std::vector<std::size_t> ok;
  for (std::size_t i = 0; i < flow.size(); ++i)
    if (flow[i].ok)
      ok.push_back(i);
  if (ok.size() < kNeighbourFlows)
    return;
  std::vector<std::pair<float, std::size_t>> by_distance(ok.size());
  std::vector<float> dx(kNeighbourFlows), dy(kNeighbourFlows);
  for (std::size_t i = 0; i < flow.size(); ++i)
  {
    // A flow that was found but does not match (occlusion, a new scene)
    // says the V-particle's place is gone: it is lost.
    if (flow[i].ok || flow[i].found)
      continue;
    for (std::size_t k = 0; k < ok.size(); ++k)
    {
      const cv::Point2f d = from[ok[k]] - from[i];
      by_distance[k] = {d.x * d.x + d.y * d.y, ok[k]};
    }
    std::partial_sort(by_distance.begin(), by_distance.begin() + kNeighbourFlows, by_distance.end());
    for (std::size_t k = 0; k < kNeighbourFlows; ++k)
    {
      const std::size_t j = by_distance[k].second;
      dx[k] = flow[j].to.x - from[j].x;
      dy[k] = flow[j].to.y - from[j].y;
    }
    std::nth_element(dx.begin(), dx.begin() + kNeighbourFlows / 2, dx.end());
    std::nth_element(dy.begin(), dy.begin() + kNeighbourFlows / 2, dy.end());
    const float x = from[i].x + dx[kNeighbourFlows / 2], y = from[i].y + dy[kNeighbourFlows / 2];
    if (x < 0.f || y < 0.f || x > image_size.width - 1.f || y > image_size.height - 1.f)
      continue;
    VParticleMove& move = moves[index[i]];
    move.kind = VParticleMove::Kind::kWithFlow;
    move.x = x;
    move.y = y;
  }
}
}  // namespace

FlowTracker::FlowTracker(const TrackingParams& params, const LifecycleRule& rule)
  : flow_(params.flow_window, params.flow_levels, params.flow_max_error), tracks_(rule)
{
}

void FlowTracker::reset()
{
  flow_.reset();
  tracks_.clear();
}

std::vector<VParticleMove> FlowTracker::follow(const std::vector<VParticle>& v, const cv::Size& image_size)
{
  // Each track's motion: a similarity fitted to the flow along its outline,
  // where the image has the edges that a flow needs.
  const std::vector<Track>& tracks = tracks_.tracks();
  std::vector<TrackMotion> motions(tracks.size());
  for (std::size_t k = 0; k < tracks.size(); ++k)
  {
    const std::vector<cv::Point2f> from = sampleOutline(tracks[k].object.outline, kOutlineFlowPoints);
    const int min_inliers = std::max(kMinTrackInliers, static_cast<int>(std::ceil(kMinTrackInlierShare * from.size())));
    motions[k].moved = estimatePatchMotion(from, flow_.track(from), min_inliers, motions[k].motion);
    for (const auto& p : tracks[k].object.outline)
      motions[k].outline.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  }

  // Each V-particle: with the motion of the track it lies on, else with the
  // Lucas-Kanade flow at its own position, which runs only for the
  // V-particles not on a tracked object; one whose flow fails moves as its
  // neighbours do (moveWithNeighbours) or is lost.
  std::vector<int> track_of(v.size(), -1);
  std::vector<cv::Point2f> free_points;
  std::vector<std::size_t> free_index(v.size(), 0);
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    track_of[i] = trackAt(motions, cv::Point2f(v[i].x, v[i].y));
    if (track_of[i] < 0)
    {
      free_index[i] = free_points.size();
      free_points.emplace_back(v[i].x, v[i].y);
    }
  }
  const std::vector<FlowVector> flow = flow_.track(free_points);
  std::vector<VParticleMove> moves(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    if (track_of[i] >= 0)
      moves[i] = moveWithTrack(v[i], motions[track_of[i]].motion, image_size);
    else if (flow[free_index[i]].ok)
    {
      moves[i].kind = VParticleMove::Kind::kWithFlow;
      moves[i].x = flow[free_index[i]].to.x;
      moves[i].y = flow[free_index[i]].to.y;
    }
  }
  std::vector<int> free_v(free_points.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    if (track_of[i] < 0)
      free_v[free_index[i]] = static_cast<int>(i);
  moveWithNeighbours(free_points, flow, image_size, moves, free_v);
  for (std::size_t k = 0; k < tracks.size(); ++k)
    if (motions[k].moved)
      tracks_.move(k, motions[k].motion);
  return moves;
}
}  // namespace amcr
