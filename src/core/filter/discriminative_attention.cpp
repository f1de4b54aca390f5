#include "amcr/filter/discriminative_attention.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/relational_update.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr float kEdgeMargin = 1.5f;  // px kept before the edge a ray met, as the exploration policy keeps

bool inCluster(const MParticleSet& m, std::size_t i, const CompetingHypothesis& h, float radius_squared)
{
  if (m.prototype[i] != h.prototype)
    return false;
  const float dx = m.x[i] - h.x, dy = m.y[i] - h.y;
  return dx * dx + dy * dy <= radius_squared;
}
}  // namespace

CompetingHypotheses competingHypotheses(const MParticleSet& m, const MRange& r, float v_x, float v_y, float radius,
                                        float min_share)
{
  CompetingHypotheses out;
  if (r.size() == 0)
    return out;
  const float radius_squared = radius * radius;
  CompetingHypotheses picked;
  for (int k = 0; k < CompetingHypotheses::kMaxCompeting; ++k)
  {
    // The most likely M-particle with an affine outside every earlier cluster.
    std::size_t best = r.end;
    float best_log_likelihood = -std::numeric_limits<float>::infinity();
    for (std::size_t i = r.begin; i < r.end; ++i)
    {
      if (m.affine_valid[i] != kFittedAffine || !(m.log_likelihood[i] > best_log_likelihood))
        continue;
      bool covered = false;
      for (int j = 0; j < picked.count && !covered; ++j)
        covered = inCluster(m, i, picked.hypothesis[j], radius_squared);
      if (!covered)
      {
        best = i;
        best_log_likelihood = m.log_likelihood[i];
      }
    }
    if (best == r.end)
      break;
    CompetingHypothesis& h = picked.hypothesis[picked.count++];
    h.prototype = m.prototype[best];
    h.x = m.x[best];
    h.y = m.y[best];
    h.image_x = v_x;
    h.image_y = v_y;
    h.linear[0] = m.affine[0][best];
    h.linear[1] = m.affine[1][best];
    h.linear[2] = m.affine[3][best];
    h.linear[3] = m.affine[4][best];
    std::size_t members = 0;
    for (std::size_t i = r.begin; i < r.end; ++i)
      members += inCluster(m, i, h, radius_squared) ? 1 : 0;
    h.share = static_cast<float>(members) / static_cast<float>(r.size());
  }
  for (int k = 0; k < picked.count; ++k)
    if (picked.hypothesis[k].share >= min_share)
      out.hypothesis[out.count++] = picked.hypothesis[k];
  return out;
}

bool decidingBetweenLookAlikes(const CompetingHypotheses& h, float converged_share)
{
  if (h.count < 2 || h.hypothesis[0].share < converged_share)
    return false;
  for (int i = 1; i < h.count; ++i)
    if (h.hypothesis[i].prototype != h.hypothesis[0].prototype)
      return true;
  return false;
}

bool hypothesisTableToImage(const CompetingHypothesis& h, Affine& table_to_image)
{
  // image -> table: t = L (p - anchor) + (x, y).
  const float* l = h.linear;
  const Affine image_to_table(l[0], l[1], h.x - l[0] * h.image_x - l[1] * h.image_y, l[2], l[3],
                              h.y - l[2] * h.image_x - l[3] * h.image_y);
  return invertAffine(image_to_table, table_to_image);
}

bool predictedRays(const Prototype& prototype, const CompetingHypothesis& h, float dx, float dy, float theta,
                   RaySignature& rays)
{
  const float* a = h.linear;
  const cv::Point at = nearestTablePixel(h.x + a[0] * dx + a[1] * dy, h.y + a[2] * dx + a[3] * dy);
  if (!insideTable(prototype, at))
    return false;
  const std::uint8_t* raw = prototype.rawDistances(at.x, at.y);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const double angle = theta + k * (2.0 * M_PI / kFeatureRays);
    const double ix = std::cos(angle), iy = std::sin(angle);
    const double tx = a[0] * ix + a[1] * iy, ty = a[2] * ix + a[3] * iy;
    const double table_per_image = std::hypot(tx, ty);  // table px per image px along this ray
    const std::uint8_t d = raw[angleToBin(std::atan2(ty, tx))];
    rays.distance[k] = (d == Prototype::kNoEdge || table_per_image < 1e-6)
                           ? 0.f
                           : std::max(1e-3f, static_cast<float>(d * Prototype::kDistanceUnit / table_per_image));
  }
  return true;
}

DiscriminativeMoveChooser::DiscriminativeMoveChooser(double step, double min_gain) : step_(step), min_gain_(min_gain)
{
}

bool DiscriminativeMoveChooser::choose(const VParticle& v, const CompetingHypotheses& h, const PrototypeMemory& memory,
                                       const ObservationModel& observation, const cv::Size& image_size,
                                       const DiscriminativePlaces* places, DiscriminativeMove& best) const
{
  if (h.count < 2 || step_ <= 0.0)
    return false;
  if (places && headForPlace(v, h, *places, image_size, best))
    return true;
  double total_share = 0.0;
  for (int i = 0; i < h.count; ++i)
    total_share += h.hypothesis[i].share;
  if (!(total_share > 0.0))
    return false;
  // One or two exploration steps: a longer move carries the M-particles
  // further on their affine A, fitted from rays of a few px, and costs more
  // of them their alignment (4 steps measured no better on `oblique`).
  const double multiples[] = {1.0, 2.0};
  RaySignature predicted[CompetingHypotheses::kMaxCompeting];
  bool found = false;
  best.gain = -1.0;
  // Turning by k * 45 deg keeps the feature rays' directions, so v.rays
  // (the last scan) tells how far each candidate can go before an edge.
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const double heading = v.theta + k * (2.0 * M_PI / kFeatureRays);
    const double cx = std::cos(heading), cy = std::sin(heading);
    const float room = v.rays.distance[k];  // 0: no edge seen on this ray
    for (double multiple : multiples)
    {
      const double length = multiple * step_;
      if (room > 0.f && length > room - kEdgeMargin)
        break;
      const double dx = length * cx, dy = length * cy;
      const double ex = v.x + dx, ey = v.y + dy;
      if (ex < 1 || ey < 1 || ex > image_size.width - 2 || ey > image_size.height - 2)
        break;
      bool inside = true;
      for (int i = 0; i < h.count && inside; ++i)
        inside = predictedRays(memory[h.hypothesis[i].prototype], h.hypothesis[i], static_cast<float>(dx),
                               static_cast<float>(dy), static_cast<float>(heading), predicted[i]);
      if (!inside)
        continue;
      // Expected divergence when the truth is drawn by the clusters' shares
      // and the alternative from the others.
      double gain = 0.0;
      for (int i = 0; i < h.count; ++i)
        for (int j = 0; j < h.count; ++j)
          if (i != j)
            gain += h.hypothesis[i].share * h.hypothesis[j].share *
                    scanDivergence(predicted[i], predicted[j], observation);
      gain /= total_share * total_share;
      if (gain > best.gain)
      {
        best.gain = gain;
        best.control.rotation = wrapAngle(heading - v.theta);
        best.control.translation = length;
        found = true;
      }
    }
  }
  return found && best.gain >= min_gain_;
}

bool DiscriminativeMoveChooser::headForPlace(const VParticle& v, const CompetingHypotheses& h,
                                             const DiscriminativePlaces& places, const cv::Size& image_size,
                                             DiscriminativeMove& best) const
{
  const CompetingHypothesis& lead = h.hypothesis[0];
  int other = 1;
  while (other < h.count && h.hypothesis[other].prototype == lead.prototype)
    ++other;
  if (other == h.count)
    return false;
  const AlikePair* pair = places.find(lead.prototype, h.hypothesis[other].prototype);
  if (!pair || pair->places.empty())
    return false;
  // The place nearest to where the leading cluster puts the V-particle.
  const DiscriminativePlace* nearest = nullptr;
  double nearest_squared = std::numeric_limits<double>::infinity();
  for (const DiscriminativePlace& p : pair->places)
  {
    const double d = (p.x - lead.x) * (p.x - lead.x) + (p.y - lead.y) * (p.y - lead.y);
    if (d < nearest_squared)
    {
      nearest_squared = d;
      nearest = &p;
    }
  }
  Affine table_to_image;
  if (!hypothesisTableToImage(lead, table_to_image))
    return false;
  const cv::Point2d target = applyAffine(table_to_image, {nearest->x, nearest->y});
  const double dx = target.x - v.x, dy = target.y - v.y, distance = std::hypot(dx, dy);
  if (!(distance > 2.0 * step_))
    return false;  // near: the candidate moves see the place's difference
  // Along the feature ray nearest the place's direction, else a neighbour:
  // only those rays' last scan tells the room before an edge.
  const double ray_angle = 2.0 * M_PI / kFeatureRays;
  const double bearing = wrapAngle(std::atan2(dy, dx) - v.theta);  // from the heading
  const int nearest_ray = static_cast<int>(std::lround(bearing / ray_angle));
  const double off = bearing - nearest_ray * ray_angle;
  const int rays[] = {nearest_ray, nearest_ray + (off > 0 ? 1 : -1), nearest_ray + (off > 0 ? -1 : 1)};
  for (int ray : rays)
  {
    const int k = ((ray % kFeatureRays) + kFeatureRays) % kFeatureRays;
    const double heading = v.theta + k * ray_angle;
    const float room = v.rays.distance[k];
    for (double multiple : {2.0, 1.0})
    {
      const double length = multiple * step_;
      const double ex = v.x + length * std::cos(heading), ey = v.y + length * std::sin(heading);
      if ((room > 0.f && length > room - kEdgeMargin) || ex < 1 || ey < 1 || ex > image_size.width - 2 ||
          ey > image_size.height - 2)
        continue;
      best.control.rotation = wrapAngle(heading - v.theta);
      best.control.translation = length;
      best.gain = nearest->divergence;
      best.to_place = true;
      return true;
    }
  }
  return false;
}
}  // namespace amcr
