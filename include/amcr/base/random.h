// The random generators of a recognizer. Every stochastic step takes one
// explicitly, so the same seed and the same input give the same output.
//
// The engine is xoshiro256** (Blackman & Vigna 2018): four words of state,
// a few cycles a draw, and a jump function that moves a generator 2^128
// draws ahead. Rng::stream(seed, k) is the k-th such jump from the seed:
// independent streams, one per V-particle, so that a V-particle's draws do
// not depend on the order (or the thread) in which the others are updated.
// Gaussians come from Boost's ziggurat normal distribution.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <boost/random/normal_distribution.hpp>

namespace amcr
{
/// xoshiro256** as a C++ UniformRandomBitGenerator (64-bit output).
class Xoshiro256
{
public:
  using result_type = std::uint64_t;

  /// The state is filled from `seed` by splitmix64, as the authors advise.
  explicit Xoshiro256(std::uint64_t seed);

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }

  result_type operator()()
  {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Moves the generator 2^128 draws ahead: the start of the next stream.
  void jump();

  bool operator==(const Xoshiro256& other) const;

private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t s_[4];
};

class Rng
{
public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  /// Streams 0..count-1 of `seed`: stream k is the generator of Rng(seed)
  /// jumped k + 1 times (2^128 draws apart: they never overlap in
  /// practice), the same whatever `count` is.
  static std::vector<Rng> streams(std::uint64_t seed, std::size_t count);

  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n), n > 0, without modulo bias.
  std::size_t index(std::size_t n)
  {
    const std::uint64_t bound = n;
    const std::uint64_t threshold = (0 - bound) % bound;  // 2^64 mod n: the draws below it would bias
    for (;;)
    {
      const std::uint64_t r = engine_();
      if (r >= threshold)
        return static_cast<std::size_t>(r % bound);
    }
  }
  /// Zero-mean Gaussian with standard deviation sigma (sigma may be 0).
  double gaussian(double sigma) { return sigma > 0.0 ? sigma * normal_(engine_) : 0.0; }

  /// The engine, for the standard library's algorithms (std::shuffle, ...).
  Xoshiro256& engine() { return engine_; }

private:
  Xoshiro256 engine_;
  // Stateless (the ziggurat keeps no second value between draws).
  boost::random::normal_distribution<double> normal_{0.0, 1.0};
};
}  // namespace amcr
