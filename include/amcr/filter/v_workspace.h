// What the work of one V-particle slot draws from and writes besides its own
// particles: its random stream and its scratch. The particle filter keeps
// one per slot, so that the slots' iterations run on several threads and
// give the same result for any thread count.
#pragma once

#include <cstdint>
#include <vector>

#include "amcr/base/random.h"
#include "amcr/filter/proposal_index.h"

namespace amcr
{
struct VWorkspace
{
  explicit VWorkspace(Rng stream) : rng(stream) {}
  Rng rng;
  std::vector<ProposalCandidate> candidates;  ///< of the V-particle being seeded or updated
  std::vector<double> weights;                ///< its M-particles' log weights at the M-resampling
  std::vector<std::uint64_t> kld_bins;        ///< KLD-sampling's occupied bins
};
}  // namespace amcr
