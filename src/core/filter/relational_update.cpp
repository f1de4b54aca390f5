#include "amcr/filter/relational_update.h"

#include <cmath>

#include "amcr/base/affine.h"

namespace amcr
{
BinDirections::BinDirections()
{
  for (int b = 0; b < kDirectionBins; ++b)
  {
    cos[b] = static_cast<float>(std::cos(binToAngle(b)));
    sin[b] = static_cast<float>(std::sin(binToAngle(b)));
  }
}

VRayEnds rayEnds(const VParticle& v, const float* distance, const bool* valid)
{
  VRayEnds ends;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const double a = v.theta + k * kFeatureBinStep * kBinAngle;
    ends.feature_dx[k] = static_cast<float>(std::cos(a));
    ends.feature_dy[k] = static_cast<float>(std::sin(a));
    ends.feature_x[k] = static_cast<float>(v.x + distance[k] * std::cos(a));
    ends.feature_y[k] = static_cast<float>(v.y + distance[k] * std::sin(a));
    ends.feature_valid[k] = valid[k];
    ends.invalid_feature_rays += valid[k] ? 0 : 1;
  }
  ends.triangle_x[0] = ends.feature_x[0];
  ends.triangle_y[0] = ends.feature_y[0];
  ends.triangle_dx[0] = ends.feature_dx[0];
  ends.triangle_dy[0] = ends.feature_dy[0];
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const double a = v.theta + t * kTriangleBinStep * kBinAngle;
    ends.triangle_dx[t] = static_cast<float>(std::cos(a));
    ends.triangle_dy[t] = static_cast<float>(std::sin(a));
    ends.triangle_x[t] = static_cast<float>(v.x + distance[kFeatureRays + t - 1] * std::cos(a));
    ends.triangle_y[t] = static_cast<float>(v.y + distance[kFeatureRays + t - 1] * std::sin(a));
  }
  ends.triangle_valid = valid[0] && valid[kFeatureRays] && valid[kFeatureRays + 1];
  return ends;
}

bool tableTriangle(const std::uint8_t* raw, const cv::Point& at, int bin, float x[kTriangleRays],
                   float y[kTriangleRays])
{
  for (int t = 0; t < kTriangleRays; ++t)
    if (!tableRayEnd(raw, at, (bin + t * kTriangleBinStep) % kDirectionBins, x[t], y[t]))
      return false;
  return true;
}

// Paper 4.1: the unique affine taking the M-particle's triangle onto the
// V-particle's; its scale check; and its inverse.
bool fitRelationalAffine(const float table_x[kTriangleRays], const float table_y[kTriangleRays], const VRayEnds& v,
                         float min_area, float max_scale, RelationalAffine& out)
{
  return affineFromTriangles(table_x, table_y, v.triangle_x, v.triangle_y, min_area, min_area, out.table_to_image) &&
         affineScaleAccepted(out.table_to_image, max_scale) && invertAffine(out.table_to_image, out.image_to_table);
}
}  // namespace amcr
