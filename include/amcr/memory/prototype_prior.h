// The context prior over prototypes (params.prototype_priors): how the
// M-particle slots of a V-particle are shared among the prototypes at
// seeding, and the prototype of an M-particle re-seeded at M-resampling.
#pragma once

#include <vector>

#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/memory/prototype_memory.h"

namespace amcr
{
class PrototypePrior
{
public:
  /// Reads params.prototype_priors (a label's weight, 1 for a label not
  /// named), params.m_particles_per_v and params.m_particles_per_prototype.
  /// ParameterError for a label the memory does not have, or when every
  /// weight is 0.
  PrototypePrior(const PrototypeMemory& memory, const ParticleCounts& params);

  /// The prototype of each of a V-particle's M-particle slots at seeding:
  /// m_particles_per_v of them (or, when it is 0, m_particles_per_prototype
  /// per prototype of non-zero weight), shared in proportion to the weights.
  const std::vector<int>& slots() const { return slots_; }

  /// The prior probability of prototype `p` (0 when its weight is 0).
  double probability(int p) const { return probability_[p]; }

  /// Whether prototype `p` has a non-zero weight, for every prototype.
  std::vector<bool> activeMask() const;

  /// A prototype drawn from the prior (one draw of `rng`).
  int draw(Rng& rng) const;

private:
  std::vector<int> slots_;
  std::vector<int> active_;    // prototypes of non-zero weight
  std::vector<double> cdf_;    // cumulative prior over active_; empty when uniform
  std::vector<double> probability_;  // per prototype of the memory
};
}  // namespace amcr
