// Systematic (low-variance) resampling, O(N) (Thrun et al., Probabilistic Robotics, table 4.4).
#pragma once

#include <vector>

#include "amcr/base/random.h"

namespace amcr
{
/// Draws `count` indices in proportion to `weights` (non-negative, need not be
/// normalised) with one uniform offset. When every weight is zero (or not
/// finite) the draw is uniform: no division by a zero total.
std::vector<int> systematicResample(const std::vector<double>& weights, int count, Rng& rng);

/// The same from log-weights (max-subtracted before exponentiation).
std::vector<int> systematicResampleLog(const std::vector<double>& log_weights, int count, Rng& rng);
}  // namespace amcr
