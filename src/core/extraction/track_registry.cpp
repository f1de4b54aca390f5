#include "amcr/extraction/track_registry.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "report_rules.h"

namespace amcr
{
namespace
{
constexpr double kOverlapGridCells = 64.0;  // cells along the longer side of the common grid
constexpr int kEndedPerObject = 4;          // ended tracks remembered, per track kept at once (max_objects)

cv::Rect2d boundsOf(const std::vector<cv::Point2d>& points)
{
  double x0 = points[0].x, x1 = x0, y0 = points[0].y, y1 = y0;
  for (const auto& p : points)
  {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}
}  // namespace

double outlineOverlap(const std::vector<cv::Point2d>& a, const std::vector<cv::Point2d>& b)
{
  if (a.size() < 3 || b.size() < 3)
    return 0.0;
  const cv::Rect2d ba = boundsOf(a), bb = boundsOf(b);
  if ((ba & bb).area() <= 0.0)
    return 0.0;
  const cv::Rect2d all = ba | bb;
  const double cell = std::max(all.width, all.height) / kOverlapGridCells;
  if (!(cell > 0.0))
    return 0.0;
  const cv::Size grid(static_cast<int>(std::ceil(all.width / cell)) + 1, static_cast<int>(std::ceil(all.height / cell)) + 1);
  const auto rasterise = [&](const std::vector<cv::Point2d>& outline) {
    std::vector<cv::Point> cells;
    cells.reserve(outline.size());
    for (const auto& p : outline)
      cells.emplace_back(static_cast<int>(std::lround((p.x - all.x) / cell)),
                         static_cast<int>(std::lround((p.y - all.y) / cell)));
    cv::Mat mask(grid, CV_8UC1, cv::Scalar(0));
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{cells}, cv::Scalar(255));
    return mask;
  };
  const cv::Mat ma = rasterise(a), mb = rasterise(b);
  const int uni = cv::countNonZero(ma | mb);
  return uni > 0 ? static_cast<double>(cv::countNonZero(ma & mb)) / uni : 0.0;
}

cv::Point2d outlineCentre(const std::vector<cv::Point2d>& outline)
{
  if (outline.empty())
    return {0.0, 0.0};
  const cv::Rect2d box = boundsOf(outline);
  return {box.x + 0.5 * box.width, box.y + 0.5 * box.height};
}

LifecycleRule::LifecycleRule(const TrackingParams& tracking, const ExtractionParams& extraction)
  : confirm_frames(tracking.confirm_frames)
  , lost_frames(tracking.lost_frames)
  , recall_frames(tracking.recall_frames)
  , max_objects(tracking.max_objects)
  , hold_score(extraction.decision_threshold)
  , rival_keep_support(extraction_steps::kKeepTrackRatio * extraction.rival_part_support)
{
}

namespace
{
/// Index of the track of `object`'s label, not taken, whose outline overlaps
/// its own most (at least `min_overlap`), or -1.
int bestOverlap(const std::vector<Track>& tracks, const RecognizedObject& object, const std::vector<bool>& taken,
                double min_overlap)
{
  int best = -1;
  double best_overlap = min_overlap;
  for (std::size_t t = 0; t < tracks.size(); ++t)
  {
    if ((t < taken.size() && taken[t]) || tracks[t].object.label != object.label)
      continue;
    const double o = outlineOverlap(tracks[t].object.outline, object.outline);
    if (o >= best_overlap)
    {
      best_overlap = o;
      best = static_cast<int>(t);
    }
  }
  return best;
}
}  // namespace

int TrackRegistry::match(const RecognizedObject& object, const std::vector<bool>& taken) const
{
  return bestOverlap(tracks_, object, taken, rule_.min_overlap);
}

int TrackRegistry::recall(const RecognizedObject& object) const
{
  return bestOverlap(ended_, object, {}, rule_.min_overlap);
}

void TrackRegistry::ageEnded()
{
  for (Track& t : ended_)
    ++t.misses;
  ended_.erase(std::remove_if(ended_.begin(), ended_.end(),
                              [this](const Track& t) { return t.misses > rule_.recall_frames; }),
               ended_.end());
}

const Track* TrackRegistry::continued(const RecognizedObject& object) const
{
  const int t = match(object, {});
  return t >= 0 ? &tracks_[t] : nullptr;
}

void TrackRegistry::assign(std::vector<RecognizedObject>& objects)
{
  std::vector<RecognizedObject> ended;
  assign(objects, cv::Size(), ended);
}

void TrackRegistry::assign(std::vector<RecognizedObject>& objects, const cv::Size& image,
                           std::vector<RecognizedObject>& ended)
{
  ageEnded();
  std::vector<Track> next;
  std::vector<bool> taken(tracks_.size(), false);
  for (auto& object : objects)
  {
    const int best = match(object, taken);
    const int recalled = best < 0 ? recall(object) : -1;
    Track track;
    if (best >= 0)
    {
      taken[best] = true;
      track = tracks_[best];
    }
    else if (recalled >= 0)
    {
      track = ended_[recalled];
      ended_.erase(ended_.begin() + recalled);
    }
    else
    {
      track.object.track_id = next_id_++;
    }
    ++track.reports;
    track.misses = 0;
    // Tentative until reported confirm_frames times; then held while the
    // tracker follows it (a new track was not followed: it is not held yet)
    // and its fit is good enough to be reported without the hysteresis.
    object.track_id = track.object.track_id;
    const bool holds = track.followed && object.score >= rule_.hold_score;
    object.state = track.reports < rule_.confirm_frames ? ObjectState::kTentative
                   : holds                              ? ObjectState::kHeld
                                                        : ObjectState::kConfirmed;
    track.object = object;
    track.followed = false;
    track.rival_misses = object.rival_support < rule_.rival_keep_support ? track.rival_misses + 1 : 0;
    next.push_back(std::move(track));
  }
  // The tracks no object continued coast, until they are lost.
  const cv::Rect2d inside(0.0, 0.0, image.width, image.height);
  for (std::size_t t = 0; t < tracks_.size(); ++t)
  {
    if (taken[t])
      continue;
    Track track = tracks_[t];
    ++track.misses;
    track.followed = false;
    const bool left = !image.empty() && !inside.contains(outlineCentre(track.object.outline));
    if (left || track.misses >= rule_.lost_frames)
    {
      track.object.state = ObjectState::kLost;
      ended.push_back(track.object);
      if (!left && rule_.recall_frames > 0)
      {
        track.misses = 0;
        ended_.push_back(std::move(track));
        if (ended_.size() > static_cast<std::size_t>(kEndedPerObject * rule_.max_objects))
          ended_.erase(ended_.begin());  // the oldest
      }
    }
    else
    {
      next.push_back(std::move(track));
    }
  }
  tracks_ = std::move(next);
}

void TrackRegistry::move(std::size_t index, const Affine& motion)
{
  mapImageSide(tracks_.at(index).object, motion);
  tracks_[index].followed = true;
}

void TrackRegistry::followAll()
{
  for (Track& t : tracks_)
    t.followed = true;
}

void TrackRegistry::clear()
{
  tracks_.clear();
  ended_.clear();
}
}  // namespace amcr
