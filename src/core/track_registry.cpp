#include "amcr/track_registry.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace amcr
{
namespace
{
constexpr double kOverlapGridCells = 64.0;  // cells along the longer side of the common grid

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

int TrackRegistry::match(const RecognizedObject& object, const std::vector<bool>& taken) const
{
  int best = -1;
  double best_overlap = min_overlap_;
  for (std::size_t t = 0; t < tracks_.size(); ++t)
  {
    if ((t < taken.size() && taken[t]) || tracks_[t].prototype_id != object.prototype_id)
      continue;
    const double o = outlineOverlap(tracks_[t].outline, object.outline);
    if (o >= best_overlap)
    {
      best_overlap = o;
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
    const int best = match(object, taken);
    if (best >= 0)
    {
      taken[best] = true;
      object.track_id = tracks_[best].id;
    }
    else
      object.track_id = next_id_++;
    next.push_back({object.track_id, object.prototype_id, object.prototype_to_image, object.outline});
  }
  tracks_ = std::move(next);
}

void TrackRegistry::move(std::size_t index, const Affine& motion)
{
  Track& t = tracks_.at(index);
  t.prototype_to_image = composeAffine(t.prototype_to_image, motion);
  for (auto& p : t.outline)
    p = applyAffine(motion, p);
}

void TrackRegistry::clear() { tracks_.clear(); }
}  // namespace amcr
