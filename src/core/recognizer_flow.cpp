// Recognition while tracking (spec "Tracking"): between frames the
// V-particles ride the optical flow, so each stays on the same object point
// and its M-particles (its places in the prototypes) stay valid; the objects
// of the last frame move with the flow along their outlines, which predicts
// where the fit starts and which track an object continues.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/recognizer.h"

namespace amcr
{
namespace
{
constexpr std::size_t kOutlineFlowPoints = 32;  // outline points whose flow gives a track's motion
constexpr double kMinTrackInlierShare = 0.4;    // of those, the share that must agree on one motion

/// Up to `count` points evenly spaced along `outline`.
std::vector<cv::Point2f> sampleOutline(const std::vector<cv::Point2d>& outline, std::size_t count)
{
  std::vector<cv::Point2f> points;
  const std::size_t step = std::max<std::size_t>(1, outline.size() / count);
  for (std::size_t i = 0; i < outline.size(); i += step)
    points.emplace_back(static_cast<float>(outline[i].x), static_cast<float>(outline[i].y));
  return points;
}
}  // namespace

int Recognizer::followFlow(const RadialScanner& scanner)
{
  // Each track's motion: a similarity fitted to the flow along its outline,
  // where the image has the edges that a flow needs.
  const std::vector<Track>& tracks = tracks_.tracks();
  std::vector<Affine> motion(tracks.size());
  std::vector<bool> moved(tracks.size(), false);
  std::vector<std::vector<cv::Point2f>> outlines(tracks.size());
  for (std::size_t k = 0; k < tracks.size(); ++k)
  {
    const std::vector<cv::Point2f> from = sampleOutline(tracks[k].outline, kOutlineFlowPoints);
    const int min_inliers = std::max(6, static_cast<int>(std::ceil(kMinTrackInlierShare * from.size())));
    moved[k] = estimatePatchMotion(from, flow_.track(from), min_inliers, motion[k]);
    for (const auto& p : tracks[k].outline)
      outlines[k].emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  }

  // Each V-particle: with the motion of the track it lies on (which also
  // turns its heading with the object, so its M-particles' headings stay
  // right), else with the Lucas-Kanade flow at its own position; a
  // V-particle whose flow fails is seeded afresh. Lucas-Kanade runs only for
  // the V-particles that are not on a tracked object.
  flow_origins_.resize(v_.size());
  std::vector<int> track_of(v_.size(), -1);
  std::vector<cv::Point2f> free_points;
  std::vector<std::size_t> free_index(v_.size(), 0);
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    flow_origins_[i] = cv::Point2f(v_[i].x, v_[i].y);
    for (std::size_t k = 0; k < tracks.size() && track_of[i] < 0; ++k)
      if (moved[k] && cv::pointPolygonTest(outlines[k], flow_origins_[i], false) >= 0)
        track_of[i] = static_cast<int>(k);
    if (track_of[i] < 0)
    {
      free_index[i] = free_points.size();
      free_points.push_back(flow_origins_[i]);
    }
  }
  const std::vector<FlowVector> flow = flow_.track(free_points);
  int failures = 0;
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    VParticle& v = v_[i];
    const int on = track_of[i];
    if (on >= 0)
    {
      const Affine& m = motion[on];
      const cv::Point2d to = applyAffine(m, cv::Point2d(v.x, v.y));
      v.x = static_cast<float>(std::min(std::max(to.x, 0.0), image_size_.width - 1.0));
      v.y = static_cast<float>(std::min(std::max(to.y, 0.0), image_size_.height - 1.0));
      v.theta = static_cast<float>(wrapAngle(v.theta + std::atan2(m(1, 0), m(0, 0))));
    }
    else if (flow[free_index[i]].ok)
    {
      v.x = flow[free_index[i]].to.x;
      v.y = flow[free_index[i]].to.y;
    }
    else
    {
      seedV(v, scanner);
      seedMRange(m_, i * per_v_, (i + 1) * per_v_, v.rays);
      ++failures;
    }
  }
  for (std::size_t k = 0; k < tracks.size(); ++k)
    if (moved[k])
      tracks_.move(k, motion[k]);
  return failures;
}
}  // namespace amcr
