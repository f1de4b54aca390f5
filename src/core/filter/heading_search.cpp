// bestHeadingBin (heading_proposal.h) with the coarse pass costed in lanes:
// the pixel's log distances laid out twice over and split by bin mod 3, so
// that feature ray k of every coarse heading (every third bin) is one
// contiguous run, and headingCost's sums kept per heading in float lanes the
// compiler vectorises. A ray that is not valid on both sides adds exactly 0
// to the sums, so each cost is bitwise that of headingCost, and the
// coarse-to-fine choice of bestHeadingBinReference (heading_proposal.cpp) is
// made again on the same costs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "amcr/filter/heading_proposal.h"

namespace amcr
{
namespace
{
constexpr int kCoarseBinStep = kHeadingCoarseBinStep;
constexpr int kCoarseBins = kDirectionBins / kCoarseBinStep;
constexpr int kPhaseLength = 2 * kCoarseBins;  // two turns of one phase (bin mod 3)

/// A pixel's log distances and validity over two turns, by phase: bin b
/// at [b % 3][b / 3], for the phases the coarse pass reads (the offsets'
/// bins mod 3: only phase 0 for the paper's, 9 k).
struct PixelLogs
{
  float log[kCoarseBinStep][kPhaseLength];
  std::int32_t valid[kCoarseBinStep][kPhaseLength];
  PixelLogs(const std::uint8_t* raw, const RayOffsets& offsets)
  {
    const std::array<float, 256>& logs = rawDistanceLogs();
    bool read[kCoarseBinStep] = {false, false, false};
    for (int k = 0; k < kFeatureRays; ++k)
      read[offsets.bin[k] % kCoarseBinStep] = true;
    for (int phase = 0; phase < kCoarseBinStep; ++phase)
      for (int c = 0; c < kCoarseBins && read[phase]; ++c)
      {
        const std::uint8_t d = raw[c * kCoarseBinStep + phase];
        log[phase][c] = log[phase][c + kCoarseBins] = logs[d];
        valid[phase][c] = valid[phase][c + kCoarseBins] = d != Prototype::kNoEdge;
      }
  }
};

/// headingCost of the coarse headings 0, 3, 6, ... (lane c: bin 3 c).
void coarseCosts(const PixelLogs& m, const LogSignature& v, const RayOffsets& offsets, float cost[kCoarseBins])
{
  float sum[kCoarseBins] = {}, sum_sq[kCoarseBins] = {}, both[kCoarseBins] = {};
  std::fill(cost, cost + kCoarseBins, 0.f);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const int phase = offsets.bin[k] % kCoarseBinStep, shift = offsets.bin[k] / kCoarseBinStep;
    const float* m_log = m.log[phase] + shift;
    const std::int32_t* m_valid = m.valid[phase] + shift;
    if (!v.valid[k])
    {
      for (int c = 0; c < kCoarseBins; ++c)
        cost[c] += m_valid[c] ? kHeadingMismatchPenalty : 0.f;
      continue;
    }
    const float v_log = v.log[k], log_scale = offsets.log_scale[k];
    for (int c = 0; c < kCoarseBins; ++c)
    {
      const bool valid = m_valid[c] != 0;
      const float any_diff = m_log[c] - log_scale - v_log;
      const float diff = valid ? any_diff : 0.f;
      sum[c] += diff;
      sum_sq[c] += diff * diff;
      both[c] += valid ? 1.f : 0.f;
      cost[c] += valid ? 0.f : kHeadingMismatchPenalty;
    }
  }
  for (int c = 0; c < kCoarseBins; ++c)
    cost[c] = both[c] > 0.f ? cost[c] + sum_sq[c] - sum[c] * sum[c] / both[c] : cost[c];
}

}  // namespace

int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature, const RayOffsets& offsets)
{
  if (signature.valid_rays() < 3)
    return -1;
  const std::uint8_t* raw = prototype.rawDistances(x, y);
  const PixelLogs m(raw, offsets);
  const LogSignature v(signature);
  float cost[kCoarseBins];
  coarseCosts(m, v, offsets, cost);
  // Coarse to fine, as bestHeadingBinReference: every third bin, then the bins around the best.
  int best_bin = 0;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int c = 0; c < kCoarseBins; ++c)
    if (cost[c] < best_cost)
    {
      best_cost = cost[c];
      best_bin = c * kCoarseBinStep;
    }
  return fineHeadingBin(raw, v, offsets, best_bin, best_cost);
}
}  // namespace amcr
