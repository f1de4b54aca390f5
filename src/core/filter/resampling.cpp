#include "amcr/filter/resampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace amcr
{
std::vector<int> systematicResample(const std::vector<double>& weights, int count, Rng& rng)
{
  std::vector<int> indices;
  if (count <= 0 || weights.empty())
    return indices;
  indices.reserve(count);
  double total = 0.0;
  for (double w : weights)
    total += (std::isfinite(w) && w > 0.0) ? w : 0.0;
  const int n = static_cast<int>(weights.size());
  const double offset = rng.uniform();
  if (!(total > 0.0) || !std::isfinite(total))
  {
    // No information: a uniform draw (never a division by a zero total).
    for (int k = 0; k < count; ++k)
      indices.push_back(std::min(n - 1, static_cast<int>((k + offset) * n / count)));
    return indices;
  }
  const double step = total / count;
  double target = offset * step;
  double cumulative = 0.0;
  int i = -1;
  for (int k = 0; k < count; ++k)
  {
    while (cumulative <= target && i < n - 1)
    {
      ++i;
      const double w = weights[i];
      cumulative += (std::isfinite(w) && w > 0.0) ? w : 0.0;
    }
    indices.push_back(i);
    target += step;
  }
  return indices;
}

std::vector<int> systematicResampleLog(const std::vector<double>& log_weights, int count, Rng& rng)
{
  double top = -std::numeric_limits<double>::infinity();
  for (double l : log_weights)
    if (std::isfinite(l))
      top = std::max(top, l);
  std::vector<double> weights(log_weights.size(), 0.0);
  if (std::isfinite(top))
    for (std::size_t i = 0; i < log_weights.size(); ++i)
      weights[i] = std::isfinite(log_weights[i]) ? std::exp(log_weights[i] - top) : 0.0;
  return systematicResample(weights, count, rng);
}
}  // namespace amcr
