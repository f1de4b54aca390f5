#include "amcr/base/affine.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace amcr
{
namespace
{
/// Twice the signed area of triangle (a, b, c).
template <typename T>
T doubleSignedArea(T ax, T ay, T bx, T by, T cx, T cy)
{
  return (bx - ax) * (cy - ay) - (cx - ax) * (by - ay);
}
}  // namespace

// The affine map of paper 4.1: with the source triangle's edge vectors
// S = [b - a, c - a] and the destination's D = [b' - a', c' - a'], the linear
// part is L = D S^-1 and the translation t = a' - L a.
bool affineFromTriangles(const cv::Point2d src[3], const cv::Point2d dst[3], double min_area, Affine& out)
{
  const double src_area2 = doubleSignedArea(src[0].x, src[0].y, src[1].x, src[1].y, src[2].x, src[2].y);
  const double dst_area2 = doubleSignedArea(dst[0].x, dst[0].y, dst[1].x, dst[1].y, dst[2].x, dst[2].y);
  const double limit = std::max(2.0 * min_area, 1e-12);
  if (std::abs(src_area2) < limit || std::abs(dst_area2) < limit)
    return false;
  const double s00 = src[1].x - src[0].x, s01 = src[2].x - src[0].x;
  const double s10 = src[1].y - src[0].y, s11 = src[2].y - src[0].y;
  const double d00 = dst[1].x - dst[0].x, d01 = dst[2].x - dst[0].x;
  const double d10 = dst[1].y - dst[0].y, d11 = dst[2].y - dst[0].y;
  const double inv = 1.0 / src_area2;  // det S
  const double i00 = s11 * inv, i01 = -s01 * inv, i10 = -s10 * inv, i11 = s00 * inv;
  const double l00 = d00 * i00 + d01 * i10, l01 = d00 * i01 + d01 * i11;
  const double l10 = d10 * i00 + d11 * i10, l11 = d10 * i01 + d11 * i11;
  out = Affine(l00, l01, dst[0].x - l00 * src[0].x - l01 * src[0].y,  //
               l10, l11, dst[0].y - l10 * src[0].x - l11 * src[0].y);
  return true;
}

bool affineFromTriangles(const float src_x[3], const float src_y[3], const float dst_x[3], const float dst_y[3],
                         float min_src_area, float min_dst_area, float out[6])
{
  const float s00 = src_x[1] - src_x[0], s01 = src_x[2] - src_x[0];
  const float s10 = src_y[1] - src_y[0], s11 = src_y[2] - src_y[0];
  const float d00 = dst_x[1] - dst_x[0], d01 = dst_x[2] - dst_x[0];
  const float d10 = dst_y[1] - dst_y[0], d11 = dst_y[2] - dst_y[0];
  const float src_area2 = s00 * s11 - s01 * s10;
  const float dst_area2 = d00 * d11 - d01 * d10;
  if (!(std::abs(src_area2) >= std::max(2.f * min_src_area, 1e-6f)) ||
      !(std::abs(dst_area2) >= std::max(2.f * min_dst_area, 1e-6f)))
    return false;
  const float inv = 1.f / src_area2;
  const float i00 = s11 * inv, i01 = -s01 * inv, i10 = -s10 * inv, i11 = s00 * inv;
  out[0] = d00 * i00 + d01 * i10;
  out[1] = d00 * i01 + d01 * i11;
  out[3] = d10 * i00 + d11 * i10;
  out[4] = d10 * i01 + d11 * i11;
  out[2] = dst_x[0] - out[0] * src_x[0] - out[1] * src_y[0];
  out[5] = dst_y[0] - out[3] * src_x[0] - out[4] * src_y[0];
  return true;
}

// The singular values s1 >= s2 of the linear part L in closed form:
// s1^2 + s2^2 = |L|_F^2 and s1 s2 = det L.
bool affineScaleAccepted(const float a[6], float max_scale)
{
  const float det = a[0] * a[4] - a[1] * a[3];
  const float frob = a[0] * a[0] + a[1] * a[1] + a[3] * a[3] + a[4] * a[4];
  const float disc = std::sqrt(std::max(0.f, frob * frob - 4.f * det * det));
  const float s1 = std::sqrt(0.5f * (frob + disc)), s2 = std::sqrt(std::max(0.f, 0.5f * (frob - disc)));
  return !(det <= 0.f || s1 > max_scale || s2 < 1.f / max_scale);
}

bool invertAffine(const float a[6], float inverse[6])
{
  const float det = a[0] * a[4] - a[1] * a[3];
  if (det == 0.f || !std::isfinite(det))
    return false;
  const float inv = 1.f / det;
  const float i0 = a[4] * inv, i1 = -a[1] * inv, i3 = -a[3] * inv, i4 = a[0] * inv;
  inverse[0] = i0;
  inverse[1] = i1;
  inverse[2] = -(i0 * a[2] + i1 * a[5]);
  inverse[3] = i3;
  inverse[4] = i4;
  inverse[5] = -(i3 * a[2] + i4 * a[5]);
  return true;
}

bool invertAffine(const Affine& a, Affine& inverse)
{
  const double det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  if (!(std::abs(det) > 1e-12) || !std::isfinite(det))
    return false;
  const double i00 = a(1, 1) / det, i01 = -a(0, 1) / det;
  const double i10 = -a(1, 0) / det, i11 = a(0, 0) / det;
  inverse = Affine(i00, i01, -(i00 * a(0, 2) + i01 * a(1, 2)),  //
                   i10, i11, -(i10 * a(0, 2) + i11 * a(1, 2)));
  return true;
}

Affine composeAffine(const Affine& first, const Affine& second)
{
  const cv::Matx33d f(first(0, 0), first(0, 1), first(0, 2), first(1, 0), first(1, 1), first(1, 2), 0, 0, 1);
  const cv::Matx33d s(second(0, 0), second(0, 1), second(0, 2), second(1, 0), second(1, 1), second(1, 2), 0, 0, 1);
  const cv::Matx33d c = s * f;
  return Affine(c(0, 0), c(0, 1), c(0, 2), c(1, 0), c(1, 1), c(1, 2));
}

void affineScales(const Affine& a, double& smallest, double& largest)
{
  // Singular values of the 2x2 linear part, closed form.
  const double p = a(0, 0), q = a(0, 1), r = a(1, 0), s = a(1, 1);
  const double e = (p + s) / 2, f = (p - s) / 2, g = (r + q) / 2, h = (r - q) / 2;
  const double qn = std::hypot(e, h), rn = std::hypot(f, g);
  largest = qn + rn;
  smallest = std::abs(qn - rn);
}

// Normal equations (3x3, Cholesky) for the two rows of the affine.
bool fitAffine(const std::vector<cv::Point2d>& from, const std::vector<cv::Point2d>& to, Affine& out)
{
  if (from.size() < 3 || from.size() != to.size())
    return false;
  cv::Matx33d ata = cv::Matx33d::zeros();
  cv::Vec3d atx(0, 0, 0), aty(0, 0, 0);
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    const cv::Vec3d r(from[i].x, from[i].y, 1.0);
    ata += r * r.t();
    atx += r * to[i].x;
    aty += r * to[i].y;
  }
  cv::Vec3d px, py;
  if (!cv::solve(ata, atx, px, cv::DECOMP_CHOLESKY) || !cv::solve(ata, aty, py, cv::DECOMP_CHOLESKY))
    return false;
  out = Affine(px[0], px[1], px[2], py[0], py[1], py[2]);
  return std::isfinite(px[0] + px[1] + px[2] + py[0] + py[1] + py[2]);
}
}  // namespace amcr
