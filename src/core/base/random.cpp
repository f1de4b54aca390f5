#include "amcr/base/random.h"

namespace amcr
{
namespace
{
// splitmix64 (Steele, Lea & Flood 2014): spreads a seed over the state.
std::uint64_t splitmix64(std::uint64_t& x)
{
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
}  // namespace

Xoshiro256::Xoshiro256(std::uint64_t seed)
{
  for (std::uint64_t& word : s_)
    word = splitmix64(seed);
}

// The authors' jump polynomial for 2^128 steps.
void Xoshiro256::jump()
{
  static constexpr std::uint64_t kJump[] = {0x180ec6d33cfd0abaULL, 0xd5a61266f0c9392cULL, 0xa9582618e03fc9aaULL,
                                            0x39abdc4529b1661cULL};
  std::uint64_t t[4] = {0, 0, 0, 0};
  for (std::uint64_t word : kJump)
    for (int b = 0; b < 64; ++b)
    {
      if (word & (std::uint64_t{1} << b))
        for (int i = 0; i < 4; ++i)
          t[i] ^= s_[i];
      (*this)();
    }
  for (int i = 0; i < 4; ++i)
    s_[i] = t[i];
}

bool Xoshiro256::operator==(const Xoshiro256& other) const
{
  for (int i = 0; i < 4; ++i)
    if (s_[i] != other.s_[i])
      return false;
  return true;
}

std::vector<Rng> Rng::streams(std::uint64_t seed, std::size_t count)
{
  std::vector<Rng> streams;
  streams.reserve(count);
  Rng next(seed);
  for (std::size_t k = 0; k < count; ++k)
  {
    next.engine_.jump();
    streams.push_back(next);
  }
  return streams;
}
}  // namespace amcr
