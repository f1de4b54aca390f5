#include "amcr/heading_proposal.h"

#include <array>
#include <cmath>
#include <limits>

namespace amcr
{
namespace
{
constexpr float kMismatchPenalty = 0.5f;  // a ray valid on one side only, in squared log units
constexpr int kCoarseBinStep = 3;         // bins between the headings of the coarse pass

/// log of every raw table value (distance in units of Prototype::kDistanceUnit).
const std::array<float, 256>& logTable()
{
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i)
      t[i] = std::log(std::max(0.25f, i * Prototype::kDistanceUnit));
    return t;
  }();
  return table;
}
}  // namespace

namespace
{
/// How badly the feature rays of direction bin `bin` match the signature:
/// the squared deviation of the log-distance differences from their mean
/// (the mean absorbs the scale), plus a penalty per validity mismatch.
float headingCost(const std::uint8_t* raw, int bin, const float* v_log, const bool* v_valid)
{
  const std::array<float, 256>& logs = logTable();
  float sum = 0.f, sum_sq = 0.f, cost = 0.f;
  int both = 0;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const std::uint8_t d = raw[(bin + k * kFeatureBinStep) % kDirectionBins];
    const bool m_valid = d != Prototype::kNoEdge;
    if (m_valid != v_valid[k])
    {
      cost += kMismatchPenalty;
      continue;
    }
    if (!m_valid)
      continue;
    const float diff = logs[d] - v_log[k];
    sum += diff;
    sum_sq += diff * diff;
    ++both;
  }
  return both > 0 ? cost + sum_sq - sum * sum / both : cost;
}
}  // namespace

int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature)
{
  if (signature.valid_rays() < 3)
    return -1;
  float v_log[kFeatureRays];
  bool v_valid[kFeatureRays];
  for (int k = 0; k < kFeatureRays; ++k)
  {
    v_valid[k] = signature.distance[k] > 0.f;
    v_log[k] = v_valid[k] ? std::log(std::max(0.25f, signature.distance[k])) : 0.f;
  }
  const std::uint8_t* raw = prototype.rawDistances(x, y);
  // Coarse to fine: every third bin (15 degrees), then the bins around the best.
  int best_bin = 0;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int bin = 0; bin < kDirectionBins; bin += kCoarseBinStep)
  {
    const float cost = headingCost(raw, bin, v_log, v_valid);
    if (cost < best_cost)
    {
      best_cost = cost;
      best_bin = bin;
    }
  }
  const int coarse = best_bin;
  for (int offset = 1 - kCoarseBinStep; offset < kCoarseBinStep; ++offset)
  {
    const int bin = (coarse + offset + kDirectionBins) % kDirectionBins;
    const float cost = offset == 0 ? best_cost : headingCost(raw, bin, v_log, v_valid);
    if (cost < best_cost)
    {
      best_cost = cost;
      best_bin = bin;
    }
  }
  return best_bin;
}
}  // namespace amcr
