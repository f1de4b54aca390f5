// A proposal for the heading of a newly seeded M-particle. The paper seeds
// M-particles uniformly; here, at the seeded pixel, the heading is the
// direction bin whose 8 table scans best match the V-particle's own scans up
// to a common scale (log distances), so a seed starts aligned with what its
// V-particle sees. It is an importance-sampling proposal: the weights that
// follow are still the likelihood of paper eq. 6.
#pragma once

#include <array>
#include <cstdint>

#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype.h"

namespace amcr
{
/// Cost of a feature ray valid on one side only, squared log units.
constexpr float kHeadingMismatchPenalty = 0.5f;

/// Bins between the headings of the searches' coarse pass (15 degrees).
constexpr int kHeadingCoarseBinStep = 3;

/// How badly the feature rays of direction bin `bin` at table pixel (x, y)
/// of `prototype` match `signature`: the squared deviation of the
/// log-distance differences from their mean (the mean absorbs the scale),
/// plus kHeadingMismatchPenalty per ray valid on one side only. The proposal
/// minimises it, coarse to fine.
float headingCost(const Prototype& prototype, int x, int y, const RaySignature& signature, int bin);

/// The direction bin at table pixel (x, y) of `prototype` whose feature rays
/// best match `signature` up to scale; -1 when the signature has fewer than
/// 3 valid rays (nothing to match: choose at random). Coarse to fine: the
/// best of every third bin, then the best of the bins around it; not always
/// the minimum over all 72 bins (test_heading_proposal.cpp says how close).
int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature);

/// Where the V-particle's feature rays land in the table under a view shape
/// (corrected_scan.h): ray k at bin offset `bin[k]` from the heading's bin
/// (the paper: 9 k) and `log_scale[k]` longer in log units than the others
/// (the paper: 0), for a V-particle of heading `v_heading`.
struct RayOffsets
{
  int bin[kFeatureRays];
  float log_scale[kFeatureRays];
  /// The offsets of view shape (xx, xy, yy) (det 1, input image frame).
  RayOffsets(const float shape[3], float v_heading);
};

/// bestHeadingBin with the rays compared at `offsets`, so that an oblique
/// view's M-particle starts aligned too; the same as the paper's for a
/// frontal shape.
/// It costs every bin at once (heading_search.cpp), with the result of
/// bestHeadingBinReference.
int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature, const RayOffsets& offsets);

/// bestHeadingBin one heading cost at a time, as first written: the plain
/// reference the fast one is tested against (test_update_loop.cpp).
int bestHeadingBinReference(const Prototype& prototype, int x, int y, const RaySignature& signature);
int bestHeadingBinReference(const Prototype& prototype, int x, int y, const RaySignature& signature,
                            const RayOffsets& offsets);

/// A signature's log distances (at least 0.25 px) and validity, as the
/// heading costs compare them.
struct LogSignature
{
  float log[kFeatureRays];
  bool valid[kFeatureRays];
  explicit LogSignature(const RaySignature& signature);
};

/// log of every raw table distance (units of Prototype::kDistanceUnit, at
/// least 0.25 px), the values headingCost compares.
const std::array<float, 256>& rawDistanceLogs();

/// headingCost on a pixel's raw table distances (Prototype::rawDistances)
/// with the feature rays at `offsets`: the one cost both heading searches
/// use (bestHeadingBin's fine pass, bestHeadingBinReference). Masked sums,
/// not branches: a ray not valid on both sides adds exactly 0 to them, as in
/// the lanes of heading_search.cpp. Inline: it runs in the seeding's hot loop.
inline float headingCost(const std::uint8_t* raw, int bin, const LogSignature& v, const RayOffsets& offsets)
{
  const std::array<float, 256>& logs = rawDistanceLogs();
  float sum = 0.f, sum_sq = 0.f, both = 0.f, cost = 0.f;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const std::uint8_t d = raw[(bin + offsets.bin[k]) % kDirectionBins];
    const bool m_valid = d != Prototype::kNoEdge;
    const bool compared = m_valid && v.valid[k];
    const float diff = compared ? logs[d] - offsets.log_scale[k] - v.log[k] : 0.f;
    sum += diff;
    sum_sq += diff * diff;
    both += compared ? 1.f : 0.f;
    cost += m_valid != v.valid[k] ? kHeadingMismatchPenalty : 0.f;
  }
  return both > 0.f ? cost + sum_sq - sum * sum / both : cost;
}
/// The fine pass of both heading searches: of the bins within
/// kHeadingCoarseBinStep - 1 of the coarse pass's choice `coarse` (whose
/// cost is `coarse_cost`), the first of least headingCost.
int fineHeadingBin(const std::uint8_t* raw, const LogSignature& v, const RayOffsets& offsets, int coarse,
                   float coarse_cost);
}  // namespace amcr
