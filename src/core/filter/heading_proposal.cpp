#include "amcr/filter/heading_proposal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

namespace amcr
{
namespace
{
}  // namespace

const std::array<float, 256>& rawDistanceLogs()
{
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i)
      t[i] = std::log(std::max(0.25f, i * Prototype::kDistanceUnit));
    return t;
  }();
  return table;
}

LogSignature::LogSignature(const RaySignature& signature)
{
  for (int k = 0; k < kFeatureRays; ++k)
  {
    valid[k] = signature.distance[k] > 0.f;
    log[k] = valid[k] ? std::log(std::max(0.25f, signature.distance[k])) : 0.f;
  }
}

namespace
{

/// The paper's offsets: ray k at 9 k bins, no scale.
const RayOffsets& frontalOffsets()
{
  static const RayOffsets offsets(kFrontalShape, 0.f);
  return offsets;
}
}  // namespace

float headingCost(const Prototype& prototype, int x, int y, const RaySignature& signature, int bin)
{
  const LogSignature v(signature);
  return headingCost(prototype.rawDistances(x, y), bin, v, frontalOffsets());
}

RayOffsets::RayOffsets(const float shape[3], float v_heading)
{
  // Relative to ray 0: the direction (degrees) and the length the shape maps
  // ray k to; the ray directions turn by 45 degrees from one to the next.
  const float turn_c = std::cos(static_cast<float>(kFeatureBinStep * kBinAngle));
  const float turn_s = std::sin(static_cast<float>(kFeatureBinStep * kBinAngle));
  float dx = std::cos(v_heading), dy = std::sin(v_heading);
  float degrees[kFeatureRays];
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const float x = shape[0] * dx + shape[1] * dy, y = shape[1] * dx + shape[2] * dy;
    degrees[k] = cv::fastAtan2(y, x);
    log_scale[k] = 0.5f * std::log(x * x + y * y);
    const float next_dx = turn_c * dx - turn_s * dy;
    dy = turn_s * dx + turn_c * dy;
    dx = next_dx;
  }
  constexpr float kBinsPerDegree = kDirectionBins / 360.f;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const int offset = static_cast<int>(std::lround((degrees[k] - degrees[0]) * kBinsPerDegree)) % kDirectionBins;
    bin[k] = offset < 0 ? offset + kDirectionBins : offset;
  }
}

int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature)
{
  return bestHeadingBin(prototype, x, y, signature, frontalOffsets());
}

int bestHeadingBinReference(const Prototype& prototype, int x, int y, const RaySignature& signature)
{
  return bestHeadingBinReference(prototype, x, y, signature, frontalOffsets());
}

int bestHeadingBinReference(const Prototype& prototype, int x, int y, const RaySignature& signature,
                            const RayOffsets& offsets)
{
  if (signature.valid_rays() < 3)
    return -1;
  const LogSignature v(signature);
  const std::uint8_t* raw = prototype.rawDistances(x, y);
  // Coarse to fine: every third bin (15 degrees), then the bins around the best.
  int best_bin = 0;
  float best_cost = std::numeric_limits<float>::infinity();
  for (int bin = 0; bin < kDirectionBins; bin += kHeadingCoarseBinStep)
  {
    const float cost = headingCost(raw, bin, v, offsets);
    if (cost < best_cost)
    {
      best_cost = cost;
      best_bin = bin;
    }
  }
  return fineHeadingBin(raw, v, offsets, best_bin, best_cost);
}

int fineHeadingBin(const std::uint8_t* raw, const LogSignature& v, const RayOffsets& offsets, int coarse,
                   float coarse_cost)
{
  int best_bin = coarse;
  float best_cost = coarse_cost;
  for (int offset = 1 - kHeadingCoarseBinStep; offset < kHeadingCoarseBinStep; ++offset)
  {
    if (offset == 0)
      continue;
    const int bin = (coarse + offset + kDirectionBins) % kDirectionBins;
    const float cost = headingCost(raw, bin, v, offsets);
    if (cost < best_cost)
    {
      best_cost = cost;
      best_bin = bin;
    }
  }
  return best_bin;
}
}  // namespace amcr
