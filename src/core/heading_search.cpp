// bestHeadingBin (heading_proposal.h) with every direction bin costed at
// once: the pixel's log distances laid out twice over, so that feature ray k
// of every heading is one contiguous run, and headingCost's sums kept per
// bin in float lanes the compiler vectorises. A ray that is not valid on both
// sides adds exactly 0 to the sums, so each bin's cost is bitwise that of
// headingCost, and the coarse-to-fine choice of bestHeadingBinReference
// (heading_proposal.cpp) is made again on the same costs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "amcr/heading_proposal.h"

namespace amcr
{
namespace
{
constexpr int kCoarseBinStep = 3;  // as in bestHeadingBinReference

/// headingCost of every direction bin at the pixel whose raw distances are `raw`.
void headingCosts(const std::uint8_t* raw, const RaySignature& signature, const RayOffsets& offsets,
                  float cost[kDirectionBins])
{
  const std::array<float, 256>& logs = rawDistanceLogs();
  float m_log[2 * kDirectionBins];
  std::int32_t m_valid[2 * kDirectionBins];
  for (int b = 0; b < kDirectionBins; ++b)
  {
    m_log[b] = m_log[b + kDirectionBins] = logs[raw[b]];
    m_valid[b] = m_valid[b + kDirectionBins] = raw[b] != Prototype::kNoEdge;
  }
  float sum[kDirectionBins] = {}, sum_sq[kDirectionBins] = {}, both[kDirectionBins] = {};
  std::fill(cost, cost + kDirectionBins, 0.f);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const float* m_log_k = m_log + offsets.bin[k];
    const std::int32_t* m_valid_k = m_valid + offsets.bin[k];
    if (!(signature.distance[k] > 0.f))
    {
      for (int b = 0; b < kDirectionBins; ++b)
        cost[b] += m_valid_k[b] ? kHeadingMismatchPenalty : 0.f;
      continue;
    }
    const float v_log = std::log(std::max(0.25f, signature.distance[k]));
    const float log_scale = offsets.log_scale[k];
    for (int b = 0; b < kDirectionBins; ++b)
    {
      const bool valid = m_valid_k[b] != 0;
      const float any_diff = m_log_k[b] - log_scale - v_log;
      const float diff = valid ? any_diff : 0.f;
      sum[b] += diff;
      sum_sq[b] += diff * diff;
      both[b] += valid ? 1.f : 0.f;
      cost[b] += valid ? 0.f : kHeadingMismatchPenalty;
    }
  }
  for (int b = 0; b < kDirectionBins; ++b)
    cost[b] = both[b] > 0.f ? cost[b] + sum_sq[b] - sum[b] * sum[b] / both[b] : cost[b];
}
}  // namespace

int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature, const RayOffsets& offsets)
{
  if (signature.valid_rays() < 3)
    return -1;
  float cost[kDirectionBins];
  headingCosts(prototype.rawDistances(x, y), signature, offsets, cost);
  // Coarse to fine, as bestHeadingBinReference: every third bin, then the bins around the best.
  int best_bin = 0;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int bin = 0; bin < kDirectionBins; bin += kCoarseBinStep)
    if (cost[bin] < best_cost)
    {
      best_cost = cost[bin];
      best_bin = bin;
    }
  const int coarse = best_bin;
  for (int offset = 1 - kCoarseBinStep; offset < kCoarseBinStep; ++offset)
  {
    const int bin = (coarse + offset + kDirectionBins) % kDirectionBins;
    const float c = offset == 0 ? best_cost : cost[bin];
    if (c < best_cost)
    {
      best_cost = c;
      best_bin = bin;
    }
  }
  return best_bin;
}
}  // namespace amcr
