#include "amcr/filter/corrected_scan.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace amcr
{
void startingShape(const float shape[4], float theta, float hx, float hy, float l[4])
{
  // The rotation that takes the mapped heading w = shape (hx, hy) onto theta.
  const float wx = shape[0] * hx + shape[1] * hy, wy = shape[2] * hx + shape[3] * hy;
  const float inverse_norm = 1.f / std::sqrt(wx * wx + wy * wy);
  const float c_theta = std::cos(theta), s_theta = std::sin(theta);
  const float c = (c_theta * wx + s_theta * wy) * inverse_norm;
  const float s = (s_theta * wx - c_theta * wy) * inverse_norm;
  l[0] = c * shape[0] - s * shape[2];
  l[1] = c * shape[1] - s * shape[3];
  l[2] = s * shape[0] + c * shape[2];
  l[3] = s * shape[1] + c * shape[3];
}

bool viewShape(const float a[6], float shape[3])
{
  // A^T A = P R^T R P = P^2, and for a 2x2 symmetric positive M,
  // sqrt(M) = (M + sqrt(det M) I) / sqrt(trace M + 2 sqrt(det M)).
  const double l00 = a[0], l01 = a[1], l10 = a[3], l11 = a[4];
  const double det = l00 * l11 - l01 * l10;
  if (!(det > 0.0) || !std::isfinite(det))
    return false;
  const double mxx = l00 * l00 + l10 * l10, mxy = l00 * l01 + l10 * l11, myy = l01 * l01 + l11 * l11;
  // det(M) = det(A)^2, so sqrt(det M) = det; P / sqrt(det P) has det 1.
  const double norm = std::sqrt(mxx + myy + 2.0 * det) * std::sqrt(det);
  shape[0] = static_cast<float>((mxx + det) / norm);
  shape[1] = static_cast<float>(mxy / norm);
  shape[2] = static_cast<float>((myy + det) / norm);
  return true;
}

float shapeAnisotropy(const float shape[3])
{
  // Singular values of a symmetric det-1 matrix: s and 1/s with s + 1/s = trace.
  const float trace = shape[0] + shape[2];
  const float s = 0.5f * (trace + std::sqrt(std::max(0.f, trace * trace - 4.f)));
  return s * s;
}

void obliqueShape(float anisotropy, float axis, float shape[3])
{
  const float c = std::cos(axis), s = std::sin(axis);
  const float stretch = std::sqrt(anisotropy), squash = 1.f / stretch;
  // R(axis) diag(stretch, squash) R(-axis)
  shape[0] = stretch * c * c + squash * s * s;
  shape[1] = (stretch - squash) * c * s;
  shape[2] = stretch * s * s + squash * c * c;
}

void diffuseShape(float e1, float e2, float shape[3])
{
  const float a = 1.f + 0.5f * e1, b = 0.5f * e2, d = 1.f - 0.5f * e1;
  // E P E with E = (a, b; b, d), both symmetric.
  const float exx = a * shape[0] + b * shape[1], exy = a * shape[1] + b * shape[2];
  const float eyx = b * shape[0] + d * shape[1], eyy = b * shape[1] + d * shape[2];
  float xx = exx * a + exy * b, xy = exx * b + exy * d, yy = eyx * b + eyy * d;
  const float det = xx * yy - xy * xy;
  if (!(det > 0.f))
    return;
  const float scale = 1.f / std::sqrt(det);
  shape[0] = xx * scale;
  shape[1] = xy * scale;
  shape[2] = yy * scale;
}

bool fitCorrectedAffine(const std::uint8_t* raw, const cv::Point& at, const float l[4], const VRayEnds& v,
                        int refits, float min_area, float max_scale, RelationalAffine& out)
{
  float shape[4] = {l[0], l[1], l[2], l[3]};
  for (int pass = 0; pass <= refits; ++pass)
  {
    float table_x[kTriangleRays], table_y[kTriangleRays];
    bool found = true;
    for (int t = 0; t < kTriangleRays && found; ++t)
      found = correctedRayEnd(raw, at, tableDirection(shape, v.triangle_dx[t], v.triangle_dy[t]), table_x[t],
                              table_y[t]);
    RelationalAffine fitted;
    if (!found || !fitRelationalAffine(table_x, table_y, v, min_area, max_scale, fitted))
      return pass > 0;
    out = fitted;
    linearPart(out, shape);
  }
  return true;
}
}  // namespace amcr
