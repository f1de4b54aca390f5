#include "amcr/track_registry.h"

#include <cmath>
#include <limits>

namespace amcr
{
namespace
{
cv::Point2d centreOf(const RecognizedObject& object)
{
  cv::Point2d sum(0, 0);
  if (object.outline.empty())
    return applyAffine(object.prototype_to_image, {0, 0});
  for (const auto& p : object.outline)
    sum += p;
  return sum * (1.0 / object.outline.size());
}
}  // namespace

int TrackRegistry::match(const RecognizedObject& object, const std::vector<bool>& taken) const
{
  const cv::Point2d centre = centreOf(object);
  int best = -1;
  double best_distance = max_distance_;
  for (std::size_t t = 0; t < tracks_.size(); ++t)
  {
    if ((t < taken.size() && taken[t]) || tracks_[t].prototype_id != object.prototype_id)
      continue;
    const double d = std::hypot(tracks_[t].centre.x - centre.x, tracks_[t].centre.y - centre.y);
    if (d <= best_distance)
    {
      best_distance = d;
      best = static_cast<int>(t);
    }
  }
  return best;
}

bool TrackRegistry::continues(const RecognizedObject& object) const { return match(object, {}) >= 0; }

void TrackRegistry::assign(std::vector<RecognizedObject>& objects)
{
  std::vector<Track> next;
  std::vector<bool> taken(tracks_.size(), false);
  for (auto& object : objects)
  {
    const cv::Point2d centre = centreOf(object);
    const int best = match(object, taken);
    if (best >= 0)
    {
      taken[best] = true;
      object.track_id = tracks_[best].id;
    }
    else
      object.track_id = next_id_++;
    next.push_back({object.track_id, object.prototype_id, centre});
  }
  tracks_ = std::move(next);
}

void TrackRegistry::reset()
{
  tracks_.clear();
  next_id_ = 1;
}
}  // namespace amcr
