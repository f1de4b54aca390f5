// The discrete ray directions of the lookup tables. 72 bins of 5 degrees hold
// both ray sets of Radial-AMCR exactly: the feature rays at k*45 degrees
// (9 bins apart) and the triangle rays at 0/120/240 degrees (24 bins apart).
#pragma once

#include <array>
#include <cmath>

namespace amcr
{
constexpr int kDirectionBins = 72;
constexpr double kBinAngle = 2.0 * M_PI / kDirectionBins;  ///< rad per bin

constexpr int kFeatureRays = 8;   ///< E_f: rays at theta + k*45 deg (spec "Radial edge scans")
constexpr int kTriangleRays = 3;  ///< E_a: rays at theta, theta + 120, theta + 240 deg

constexpr int kFeatureBinStep = kDirectionBins / kFeatureRays;    // 9
constexpr int kTriangleBinStep = kDirectionBins / kTriangleRays;  // 24

/// Bin of an angle in rad, rounded to the nearest bin, in [0, kDirectionBins).
inline int angleToBin(double angle)
{
  int bin = static_cast<int>(std::lround(angle / kBinAngle)) % kDirectionBins;
  return bin < 0 ? bin + kDirectionBins : bin;
}

inline double binToAngle(int bin) { return bin * kBinAngle; }

/// Wraps an angle to (-pi, pi].
inline double wrapAngle(double angle)
{
  angle = std::fmod(angle + M_PI, 2.0 * M_PI);
  if (angle < 0)
    angle += 2.0 * M_PI;
  return angle - M_PI;
}
}  // namespace amcr
