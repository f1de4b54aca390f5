#include "amcr/filter/ray_divergence.h"

#include <algorithm>

namespace amcr
{
// Eq. 6 compares each valid ray by eq. 5 and gives an invalid one p_invalid:
// the log-likelihood the hypothesis predicting `a` loses against the one
// predicting `b` when `a` is what the image shows.
double rayDivergence(float a, float b, const ObservationModel& observation)
{
  const bool valid_a = a > 0.f, valid_b = b > 0.f;
  const double best = observation.logRayFromSquared(0.f);
  if (valid_a && valid_b)
  {
    const float d = a - b;
    return std::max(0.0, best - observation.logRayFromSquared(d * d));
  }
  return valid_a != valid_b ? std::max(0.0, best - observation.logInvalid()) : 0.0;
}

double scanDivergence(const RaySignature& a, const RaySignature& b, const ObservationModel& observation)
{
  double sum = 0.0;
  for (int k = 0; k < kFeatureRays; ++k)
    sum += rayDivergence(a.distance[k], b.distance[k], observation);
  return sum;
}
}  // namespace amcr
