// What the objects the tracker holds change in the particle filter: no
// V-particle starts on them (inhibition of return), and new M-particles
// lean towards their prototypes (the scene's context). V-resampling's share
// of them is in particle_filter_resampling.cpp (keepOnHeldObjects).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/filter/particle_filter.h"

namespace amcr
{
namespace
{
constexpr int kFreePlaceDraws = 32;  // uniform draws before a free place is picked from the mask's free pixels
}  // namespace

// Inhibition of return (spec "Attention that moves on"): what a held object
// shows is explained, so no V-particle starts there.
cv::Point2f ParticleFilter::drawFreePlace(Rng& rng) const
{
  const auto draw = [this, &rng] {
    // x before y, in two statements: the order of a call's arguments is unspecified.
    const float x = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size_.width - 2.0)));
    const float y = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size_.height - 2.0)));
    return cv::Point2f(x, y);
  };
  cv::Point2f place = draw();
  if (held_v_.empty())
    return place;
  for (int k = 1; k < kFreePlaceDraws && heldObjectAt(place.x, place.y) >= 0; ++k)
    place = draw();
  if (heldObjectAt(place.x, place.y) < 0)
    return place;
  // Held objects cover most of the image: a free pixel, if there is one.
  std::vector<cv::Point> free;
  cv::findNonZero(held_mask_ == 0, free);
  if (free.empty())
    return place;
  const cv::Point& at = free[rng.index(free.size())];
  return cv::Point2f(static_cast<float>(at.x), static_cast<float>(at.y));
}

void ParticleFilter::setHeldObjects(const std::vector<HeldObject>& held)
{
  for (std::size_t k = 0; k < held.size(); ++k)
    if (held[k].prototype < 0 || held[k].prototype >= static_cast<int>(memory_->size()))
      throw InputError("setHeldObjects: held object " + std::to_string(k) + " names prototype " +
                       std::to_string(held[k].prototype) + ", not in the memory of " +
                       std::to_string(memory_->size()) + " prototypes");
  held_mask_.release();
  held_v_.clear();
  held_prototypes_.clear();
  if (held.empty() || image_size_.empty())
    return;
  held_mask_ = cv::Mat::zeros(image_size_, CV_16UC1);
  for (const HeldObject& object : held)
  {
    held_v_.push_back(object.v_particles);
    if (prior_.probability(object.prototype) > 0.0)  // a prior of 0 keeps a prototype out
      held_prototypes_.push_back(object.prototype);
    if (object.outline.size() < 3)
      continue;
    // The hull: a V-particle in a concavity of the object sees the object.
    std::vector<cv::Point> points, hull;
    for (const cv::Point2d& p : object.outline)
      points.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    cv::convexHull(points, hull);
    cv::fillConvexPoly(held_mask_, hull, cv::Scalar(static_cast<double>(held_v_.size())));  // k + 1
  }
}

int ParticleFilter::heldObjectAt(float x, float y) const
{
  const int col = static_cast<int>(std::lround(x)), row = static_cast<int>(std::lround(y));
  if (held_v_.empty() || col < 0 || row < 0 || col >= held_mask_.cols || row >= held_mask_.rows)
    return -1;
  return static_cast<int>(held_mask_.at<std::uint16_t>(row, col)) - 1;
}

// The scene's context (the paper's context priors, spec "Context priors"):
// what is held is likely to be in view again, as a copy, so the prior of new
// M-particles leans towards it.
int ParticleFilter::scenePrototype(int slot, Rng& rng) const
{
  if (held_prototypes_.empty() || params_.scene_prior_share <= 0.0 || rng.uniform() >= params_.scene_prior_share)
    return slot;
  return held_prototypes_[rng.index(held_prototypes_.size())];
}

double ParticleFilter::seedingProbability(int p) const
{
  if (held_prototypes_.empty() || params_.scene_prior_share <= 0.0)
    return prior_.probability(p);
  const double held = static_cast<double>(std::count(held_prototypes_.begin(), held_prototypes_.end(), p));
  return (1.0 - params_.scene_prior_share) * prior_.probability(p) +
         params_.scene_prior_share * held / static_cast<double>(held_prototypes_.size());
}
}  // namespace amcr
