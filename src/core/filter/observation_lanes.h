// What ObservationModel::measure's lanes share between the per-bin lookups
// (observation_model_lanes.cpp) and the corrected lookups of ray_correspondence
// affine (corrected_scan_lanes.cpp): a block of kLanes M-particles as
// structure-of-arrays lanes. Private to src/core.
#pragma once

#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "amcr/filter/particles.h"
#include "amcr/filter/relational_update.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace measure_lanes
{
constexpr std::size_t kLanes = 32;  // M-particles per block

/// The direction bins of the feature and triangle rays of every heading
/// bin, and half of each bin's direction (the step of one raw distance unit,
/// Prototype::kDistanceUnit: halving is exact, so raw * half_cos is bitwise
/// raw * kDistanceUnit * cos).
struct HeadingRayBins
{
  std::uint8_t feature[kDirectionBins][kFeatureRays];
  std::uint8_t triangle[kDirectionBins][kTriangleRays];
  float half_cos[kDirectionBins];
  float half_sin[kDirectionBins];
  HeadingRayBins()
  {
    static_assert(Prototype::kDistanceUnit == 0.5f, "half_cos and half_sin are the steps of 0.5 px");
    for (int b = 0; b < kDirectionBins; ++b)
    {
      half_cos[b] = 0.5f * binDirections().cos[b];
      half_sin[b] = 0.5f * binDirections().sin[b];
      for (int k = 0; k < kFeatureRays; ++k)
        feature[b][k] = static_cast<std::uint8_t>((b + k * kFeatureBinStep) % kDirectionBins);
      for (int t = 0; t < kTriangleRays; ++t)
        triangle[b][t] = static_cast<std::uint8_t>((b + t * kTriangleBinStep) % kDirectionBins);
    }
  }
};

/// The bins of every heading, built once.
const HeadingRayBins& headingRayBins();

/// One block's M-particles as lanes: the table ends of their triangle rays
/// and of the feature rays valid in v (index j of v's valid rays), and
/// whether each met an edge.
struct TableEndLanes
{
  float triangle_x[kTriangleRays][kLanes];
  float triangle_y[kTriangleRays][kLanes];
  std::int32_t triangle_found[kLanes];
  float ray_x[kFeatureRays][kLanes];
  float ray_y[kFeatureRays][kLanes];
  std::int32_t ray_found[kFeatureRays][kLanes];
};

/// The relational affine of each lane: B (table -> image), A = B^-1, and
/// whether the fit is accepted.
struct AffineLanes
{
  float b[6][kLanes];
  float a[6][kLanes];
  std::int32_t accepted[kLanes];
};

/// The triangle ends of each lane read along its view shape, as
/// fitCorrectedAffine's first pass reads them (corrected_scan_lanes.cpp).
void correctedTriangleEnds(const MParticleSet& m, std::size_t begin, std::size_t lanes,
                           const std::uint8_t* const raw[], const cv::Point at[], const VRayEnds& v,
                           const HeadingRayBins& bins, TableEndLanes& ends);

/// The ends of v's valid feature rays read along the fitted A, for the
/// accepted lanes (corrected_scan_lanes.cpp).
void correctedFeatureEnds(const AffineLanes& affine, std::size_t lanes, const std::uint8_t* const raw[],
                          const cv::Point at[], const VRayEnds& v, const int* valid_rays, int valid_count,
                          const HeadingRayBins& bins, TableEndLanes& ends);
}  // namespace measure_lanes
}  // namespace amcr
