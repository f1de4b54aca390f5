#include "amcr/base/homography.h"

#include <cmath>
#include <limits>

namespace amcr
{
Homography liftAffine(const Affine& a)
{
  return Homography(a(0, 0), a(0, 1), a(0, 2), a(1, 0), a(1, 1), a(1, 2), 0.0, 0.0, 1.0);
}

cv::Point2d applyHomography(const Homography& h, const cv::Point2d& p)
{
  const double w = h(2, 0) * p.x + h(2, 1) * p.y + h(2, 2);
  if (!(w > 0.0))
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  return {(h(0, 0) * p.x + h(0, 1) * p.y + h(0, 2)) / w, (h(1, 0) * p.x + h(1, 1) * p.y + h(1, 2)) / w};
}

bool normalizeHomography(const Homography& h, Homography& out)
{
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(h.val[i]))
      return false;
  if (h(2, 2) == 0.0)
    return false;
  out = h * (1.0 / h(2, 2));
  out(2, 2) = 1.0;
  return true;
}

Homography composeHomography(const Homography& first, const Homography& second)
{
  const Homography product = second * first;
  Homography out = product;
  normalizeHomography(product, out);
  return out;
}

bool homographyJacobian(const Homography& h, const cv::Point2d& p, cv::Matx22d& jacobian)
{
  const double w = h(2, 0) * p.x + h(2, 1) * p.y + h(2, 2);
  if (!(w > 0.0))
    return false;
  const double u = (h(0, 0) * p.x + h(0, 1) * p.y + h(0, 2)) / w;
  const double v = (h(1, 0) * p.x + h(1, 1) * p.y + h(1, 2)) / w;
  // d(x'/w)/dx = (h00 - x' h20) / w, and so on.
  jacobian = cv::Matx22d((h(0, 0) - u * h(2, 0)) / w, (h(0, 1) - u * h(2, 1)) / w, (h(1, 0) - v * h(2, 0)) / w,
                         (h(1, 1) - v * h(2, 1)) / w);
  return true;
}
}  // namespace amcr
