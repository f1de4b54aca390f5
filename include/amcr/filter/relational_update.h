// The geometry of the relational update (paper 3.6, 4.1): the ray end points
// of a V-particle in the input image and of an M-particle in its prototype's
// table, and the triangle affine between them. ObservationModel::measure
// (observation_model.h) runs the whole update, eqs. 5-6 included, over the
// M-particles of one V-particle; the pieces are here so that each has a name
// and a test.
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
/// A V-particle's ray end points in the input image, px.
struct VRayEnds
{
  float feature_x[kFeatureRays];     ///< end of feature ray k (theta + k * 45 deg)
  float feature_y[kFeatureRays];
  bool feature_valid[kFeatureRays];  ///< whether feature ray k met an edge
  int invalid_feature_rays = 0;      ///< how many feature rays met none
  float triangle_x[kTriangleRays];   ///< end of triangle ray t (theta + t * 120 deg); t = 0 is feature ray 0
  float triangle_y[kTriangleRays];
  bool triangle_valid = false;       ///< whether all three triangle rays met an edge
  float feature_dx[kFeatureRays];    ///< unit direction of feature ray k in the input image
  float feature_dy[kFeatureRays];
  float triangle_dx[kTriangleRays];  ///< unit direction of triangle ray t in the input image
  float triangle_dy[kTriangleRays];
};

/// The ray end points of `v`. `distance` and `valid` hold the 8 feature rays
/// then the 2 further triangle rays (120, 240 deg), px; ray 0 serves both
/// sets. The distance of an invalid ray is not used.
VRayEnds rayEnds(const VParticle& v, const float* distance, const bool* valid);

/// The table pixel nearest to an M-particle's position (x, y), table px.
inline cv::Point nearestTablePixel(float x, float y)
{
  // The offset keeps the rounding right for small negative values.
  return {static_cast<int>(x + 1024.5f) - 1024, static_cast<int>(y + 1024.5f) - 1024};
}

/// Whether `pixel` lies inside the table of `prototype`.
inline bool insideTable(const Prototype& prototype, const cv::Point& pixel)
{
  return pixel.x >= 0 && pixel.y >= 0 && pixel.x < prototype.width() && pixel.y < prototype.height();
}

/// cos and sin of every direction bin, float.
struct BinDirections
{
  float cos[kDirectionBins];
  float sin[kDirectionBins];
  BinDirections();
};

inline const BinDirections& binDirections()
{
  static const BinDirections directions;
  return directions;
}

/// Where the ray of direction bin `bin` from table pixel `at` ends, table px,
/// given the raw distances of `at` (Prototype::rawDistances); false when the
/// ray meets no edge.
inline bool tableRayEnd(const std::uint8_t* raw, const cv::Point& at, int bin, float& x, float& y)
{
  if (raw[bin] == Prototype::kNoEdge)
    return false;
  const BinDirections& dir = binDirections();
  x = at.x + raw[bin] * Prototype::kDistanceUnit * dir.cos[bin];
  y = at.y + raw[bin] * Prototype::kDistanceUnit * dir.sin[bin];
  return true;
}

/// The end points of the three triangle rays (bins `bin`, +120 deg, +240 deg)
/// of an M-particle at table pixel `at`; false when one meets no edge.
bool tableTriangle(const std::uint8_t* raw, const cv::Point& at, int bin, float x[kTriangleRays],
                   float y[kTriangleRays]);

/// The affine of a relational particle (paper 4.1), row-major 2x3 each.
struct RelationalAffine
{
  float table_to_image[6];  ///< B: takes the M-particle's triangle onto the V-particle's
  float image_to_table[6];  ///< A = B^-1, stored in the M-particle
};

/// B from the triangle correspondences (table triangle -> v's triangle) and
/// A = B^-1. False when either triangle has an area below `min_area` px^2,
/// or B is mirrored or scales by more than `max_scale` either way (a
/// physical print is neither); `out` is then unspecified.
bool fitRelationalAffine(const float table_x[kTriangleRays], const float table_y[kTriangleRays], const VRayEnds& v,
                         float min_area, float max_scale, RelationalAffine& out);

/// dw^2 of paper eq. 5 for one feature ray ending at (table_x, table_y) in the
/// table and at (image_x, image_y) in the input image: in input px
/// (B p'_j - p_j) or, as in the paper, in prototype px (p'_j - A p_j).
inline float squaredDeviation(const RelationalAffine& affine, DeviationSpace space, float table_x, float table_y,
                              float image_x, float image_y)
{
  float dx, dy;
  if (space == DeviationSpace::kImage)
  {
    const float* b = affine.table_to_image;
    dx = b[0] * table_x + b[1] * table_y + b[2] - image_x;
    dy = b[3] * table_x + b[4] * table_y + b[5] - image_y;
  }
  else
  {
    const float* a = affine.image_to_table;
    dx = a[0] * image_x + a[1] * image_y + a[2] - table_x;
    dy = a[3] * image_x + a[4] * image_y + a[5] - table_y;
  }
  return dx * dx + dy * dy;
}
}  // namespace amcr
