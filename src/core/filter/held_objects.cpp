#include "amcr/filter/held_objects.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
constexpr int kFreePlaceDraws = 32;  // uniform draws before a free place is picked from the mask's free pixels
}  // namespace

HeldObjects::HeldObjects(const AttentionParams& attention)
  : keep_per_object_(attention.held_v_particles), scene_prior_share_(attention.scene_prior_share)
{
}

void HeldObjects::set(const std::vector<HeldObject>& held, const cv::Size& image_size, const PrototypePrior& prior,
                      std::size_t prototypes)
{
  for (std::size_t k = 0; k < held.size(); ++k)
    if (held[k].prototype < 0 || held[k].prototype >= static_cast<int>(prototypes))
      throw InputError("setHeldObjects: held object " + std::to_string(k) + " names prototype " +
                       std::to_string(held[k].prototype) + ", not in the memory of " + std::to_string(prototypes) +
                       " prototypes");
  clear();
  if (held.empty() || image_size.empty())
    return;
  mask_ = cv::Mat::zeros(image_size, CV_16UC1);
  for (const HeldObject& object : held)
  {
    supporters_.push_back(object.v_particles);
    if (prior.probability(object.prototype) > 0.0)  // a prior of 0 keeps a prototype out
      prototypes_.push_back(object.prototype);
    if (object.outline.size() < 3)
      continue;
    // The hull: a V-particle in a concavity of the object sees the object.
    std::vector<cv::Point> points, hull;
    for (const cv::Point2d& p : object.outline)
      points.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    cv::convexHull(points, hull);
    cv::fillConvexPoly(mask_, hull, cv::Scalar(static_cast<double>(supporters_.size())));  // k + 1
  }
}

void HeldObjects::clear()
{
  mask_.release();
  supporters_.clear();
  prototypes_.clear();
}

int HeldObjects::at(float x, float y) const
{
  const int col = static_cast<int>(std::lround(x)), row = static_cast<int>(std::lround(y));
  if (supporters_.empty() || col < 0 || row < 0 || col >= mask_.cols || row >= mask_.rows)
    return -1;
  return static_cast<int>(mask_.at<std::uint16_t>(row, col)) - 1;
}

// Inhibition of return (spec "Attention that moves on"): what a held object
// shows is explained, so no V-particle starts there.
cv::Point2f HeldObjects::drawFreePlace(const cv::Size& image_size, Rng& rng) const
{
  const auto draw = [&image_size, &rng] {
    // x before y, in two statements: the order of a call's arguments is unspecified.
    const float x = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size.width - 2.0)));
    const float y = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size.height - 2.0)));
    return cv::Point2f(x, y);
  };
  cv::Point2f place = draw();
  if (supporters_.empty())
    return place;
  for (int k = 1; k < kFreePlaceDraws && at(place.x, place.y) >= 0; ++k)
    place = draw();
  if (at(place.x, place.y) < 0)
    return place;
  // Held objects cover most of the image: a free pixel, if there is one.
  std::vector<cv::Point> free;
  cv::findNonZero(mask_ == 0, free);
  if (free.empty())
    return place;
  const cv::Point& found = free[rng.index(free.size())];
  return cv::Point2f(static_cast<float>(found.x), static_cast<float>(found.y));
}

// The scene's context (the paper's context priors, spec "Context priors"):
// what is held is likely to be in view again, as a copy, so the prior of new
// M-particles leans towards it.
int HeldObjects::scenePrototype(int slot, Rng& rng) const
{
  if (prototypes_.empty() || scene_prior_share_ <= 0.0 || rng.uniform() >= scene_prior_share_)
    return slot;
  return prototypes_[rng.index(prototypes_.size())];
}

double HeldObjects::seedingProbability(int p, const PrototypePrior& prior) const
{
  if (prototypes_.empty() || scene_prior_share_ <= 0.0)
    return prior.probability(p);
  const double held = static_cast<double>(std::count(prototypes_.begin(), prototypes_.end(), p));
  return (1.0 - scene_prior_share_) * prior.probability(p) +
         scene_prior_share_ * held / static_cast<double>(prototypes_.size());
}

std::vector<int> HeldObjects::keep(const std::vector<VParticle>& v, std::vector<double>& log_weights) const
{
  std::vector<int> kept;
  const int held = static_cast<int>(supporters_.size());
  if (held == 0)
    return kept;
  // Each V-particle on at most one held object: the one it supports, else
  // the one whose hull holds it.
  std::vector<int> on(v.size(), -1);
  for (int h = 0; h < held; ++h)
    for (int i : supporters_[h])
      if (i >= 0 && i < static_cast<int>(v.size()))
        on[i] = h;
  std::vector<std::vector<int>> inside(held);
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    const int h = on[i] >= 0 ? on[i] : at(v[i].x, v[i].y);
    if (h >= 0)
      inside[h].push_back(static_cast<int>(i));
  }
  // Together the held objects keep at most half of the V-particles.
  const std::size_t keep = static_cast<std::size_t>(
      std::min(keep_per_object_, std::max(1, static_cast<int>(v.size()) / (2 * held))));
  for (std::vector<int>& members : inside)
  {
    std::stable_sort(members.begin(), members.end(), [&](int a, int b) { return log_weights[a] > log_weights[b]; });
    for (std::size_t k = 0; k < members.size() && k < keep; ++k)
      kept.push_back(members[k]);
    for (int i : members)
      log_weights[i] = -std::numeric_limits<double>::infinity();
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}
}  // namespace amcr
