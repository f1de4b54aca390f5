#include "amcr/filter/exploration_policy.h"

#include <cmath>

#include "amcr/scan/ray_directions.h"

namespace amcr
{
ReflectAtEdgesPolicy::ReflectAtEdgesPolicy(double step, double jitter) : step_(step), jitter_(jitter) {}

// Paper 4.3: "a V-particle could always move forward and be reflected at an
// edge in the image", so it explores the shape it is on.
Control ReflectAtEdgesPolicy::decide(const VParticle& v, const RadialScanner& scanner, Rng& rng) const
{
  Control u;
  if (step_ <= 0.0)
    return u;
  const float margin = 1.5f;  // px kept between a V-particle and the edge it turns at
  const double dx = std::cos(v.theta), dy = std::sin(v.theta);
  const RayHit ahead = scanner.scan(v.x, v.y, static_cast<float>(dx), static_cast<float>(dy));
  const double room = ahead.valid ? ahead.distance - margin : step_;
  const double ex = v.x + step_ * dx, ey = v.y + step_ * dy;
  const int cols = scanner.image().cols, rows = scanner.image().rows;
  const bool leaves_image = ex < 1 || ey < 1 || ex > cols - 2 || ey > rows - 2;
  if (room >= step_ && !leaves_image)
  {
    u.translation = step_;
    return u;
  }
  // Reflect: about the edge's normal, or the image border's.
  double nx = 0, ny = 0;
  if (leaves_image)
  {
    nx = (ex < 1) ? 1 : (ex > cols - 2 ? -1 : 0);
    ny = (ey < 1) ? 1 : (ey > rows - 2 ? -1 : 0);
  }
  else
  {
    const cv::Point2f n = scanner.edgeNormal(static_cast<float>(v.x + ahead.distance * dx),
                                             static_cast<float>(v.y + ahead.distance * dy));
    nx = n.x;
    ny = n.y;
  }
  const double norm = std::hypot(nx, ny);
  double rx = -dx, ry = -dy;  // no usable normal: turn back
  if (norm > 1e-6)
  {
    nx /= norm;
    ny /= norm;
    const double dot = dx * nx + dy * ny;
    rx = dx - 2 * dot * nx;
    ry = dy - 2 * dot * ny;
  }
  const double heading = std::atan2(ry, rx) + rng.uniform(-jitter_, jitter_);
  u.rotation = wrapAngle(heading - v.theta);
  // Move along the new heading only as far as there is room.
  const RayHit after = scanner.scanAngle(v.x, v.y, heading);
  const double free = after.valid ? after.distance - margin : step_;
  u.translation = std::max(0.0, std::min(step_, free));
  const double fx = v.x + u.translation * std::cos(heading), fy = v.y + u.translation * std::sin(heading);
  if (fx < 1 || fy < 1 || fx > cols - 2 || fy > rows - 2)
    u.translation = 0.0;
  return u;
}
}  // namespace amcr
