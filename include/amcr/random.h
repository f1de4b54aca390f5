// The one random generator of a recognizer. It is passed explicitly to every
// stochastic step, so the same seed and the same input give the same output.
#pragma once

#include <cstdint>
#include <random>

namespace amcr
{
class Rng
{
public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1).
  double uniform() { return std::uniform_real_distribution<double>(0.0, 1.0)(engine_); }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0.
  std::size_t index(std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(engine_); }
  /// Zero-mean Gaussian with standard deviation sigma (sigma may be 0).
  double gaussian(double sigma) { return sigma > 0.0 ? sigma * normal_(engine_) : 0.0; }

  std::mt19937_64& engine() { return engine_; }

private:
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};
}  // namespace amcr
