// The triangle affine estimator E_a (paper 4.1, spec "Radial edge scans")
// and the affine helpers: exactness on random triangles, refusal of
// degenerate ones, and the group invariants (style point 8).
#include <algorithm>
#include <cmath>
#include <string>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/affine.h"

namespace
{
using amcr::Affine;

// Twice the signed area of a triangle.
double twiceArea(const cv::Point2d p[3])
{
  return (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
}

// A random affine whose linear part has singular values in [0.3, 3] (well
// conditioned, either orientation) and a translation of up to 300 px.
Affine randomAffine(std::mt19937_64& gen)
{
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_scale(std::log(0.3), std::log(3.0)),
      shift(-300.0, 300.0), coin(0.0, 1.0);
  const double a = angle(gen), b = angle(gen);
  const double s1 = std::exp(log_scale(gen)), s2 = std::exp(log_scale(gen));
  const double flip = coin(gen) < 0.2 ? -1.0 : 1.0;
  const cv::Matx22d r1(std::cos(a), -std::sin(a), std::sin(a), std::cos(a));
  const cv::Matx22d r2(std::cos(b), -std::sin(b), std::sin(b), std::cos(b));
  const cv::Matx22d l = r1 * cv::Matx22d(s1, 0, 0, flip * s2) * r2;
  // One draw per statement (a call's arguments come in no set order), the last argument's first.
  const double ty = shift(gen);
  const double tx = shift(gen);
  return Affine(l(0, 0), l(0, 1), tx, l(1, 0), l(1, 1), ty);
}

// Three random points in a 640x480 image forming a non-degenerate triangle:
// area >= 500 px^2 (so its image under randomAffine has >= 0.09 * 500) and
// every altitude >= 5 px.
void randomTriangle(std::mt19937_64& gen, cv::Point2d p[3])
{
  std::uniform_real_distribution<double> x(0.0, 639.0), y(0.0, 479.0);
  const auto longest_side = [&]() {
    double l = 0.0;
    for (int i = 0; i < 3; ++i)
      l = std::max(l, std::hypot(p[i].x - p[(i + 1) % 3].x, p[i].y - p[(i + 1) % 3].y));
    return l;
  };
  do
  {
    for (int i = 0; i < 3; ++i)
      p[i] = {x(gen), y(gen)};
  } while (std::abs(twiceArea(p)) < 2.0 * 500.0 || std::abs(twiceArea(p)) / longest_side() < 5.0);
}

double maxAbsDiff(const Affine& a, const Affine& b)
{
  double d = 0.0;
  for (int i = 0; i < 6; ++i)
    d = std::max(d, std::abs(a.val[i] - b.val[i]));
  return d;
}

TEST(AffineFromTriangles, RecoversRandomAffinesExactly)
{
  std::mt19937_64 gen(2024);
  for (int trial = 0; trial < 2000; ++trial)
  {
    const Affine truth = randomAffine(gen);
    cv::Point2d src[3], dst[3];
    randomTriangle(gen, src);
    for (int i = 0; i < 3; ++i)
      dst[i] = amcr::applyAffine(truth, src[i]);

    Affine estimate(0, 0, 0, 0, 0, 0);
    ASSERT_TRUE(amcr::affineFromTriangles(src, dst, 1.0, estimate)) << "trial " << trial;
    // Coefficients up to 300 px: 1e-6 absolute is ~1e-9 relative.
    EXPECT_LT(maxAbsDiff(estimate, truth), 1e-6) << "trial " << trial;
    for (int i = 0; i < 3; ++i)
    {
      const cv::Point2d q = amcr::applyAffine(estimate, src[i]);
      EXPECT_NEAR(q.x, dst[i].x, 1e-6);
      EXPECT_NEAR(q.y, dst[i].y, 1e-6);
    }
  }
}

// The float overload as the hot loop uses it: a triangle in a prototype
// table (up to 200 px) onto a triangle in the input image (640 x 480), and
// back. The truth is a random similarity-with-shear whose image of the table
// lands in the input image.
TEST(AffineFromTriangles, FloatVersionRecoversRandomAffines)
{
  std::mt19937_64 gen(77);
  std::uniform_real_distribution<double> table(0.0, 199.0), angle(-M_PI, M_PI), log_scale(std::log(0.4), std::log(2.5)),
      shear(-0.4, 0.4);
  double worst_point = 0.0, worst_linear = 0.0;
  int tested = 0;
  while (tested < 2000)
  {
    // Table -> image: R(a) [1 sh; 0 1] diag(sx, sy), centred on the image.
    const double a = angle(gen), sx = std::exp(log_scale(gen)), sy = std::exp(log_scale(gen)), sh = shear(gen);
    const cv::Matx22d l = cv::Matx22d(std::cos(a), -std::sin(a), std::sin(a), std::cos(a)) * cv::Matx22d(1, sh, 0, 1) *
                          cv::Matx22d(sx, 0, 0, sy);
    const cv::Vec2d t = cv::Vec2d(320, 240) - l * cv::Vec2d(100, 100);
    const Affine truth(l(0, 0), l(0, 1), t[0], l(1, 0), l(1, 1), t[1]);
    Affine truth_inverse;
    ASSERT_TRUE(amcr::invertAffine(truth, truth_inverse));

    cv::Point2d src[3];
    for (int i = 0; i < 3; ++i)
      src[i] = {table(gen), table(gen)};
    // Non-degenerate: area >= 100 px^2 and every altitude >= 5 px. (A thin
    // triangle is ill-conditioned: float rounding alone then moves the
    // solution by more than 1e-3 px, whatever the solver.)
    double longest = 0.0;
    for (int i = 0; i < 3; ++i)
      longest = std::max(longest, std::hypot(src[i].x - src[(i + 1) % 3].x, src[i].y - src[(i + 1) % 3].y));
    if (std::abs(twiceArea(src)) < 200.0 || std::abs(twiceArea(src)) / longest < 5.0)
      continue;
    ++tested;
    float tx[3], ty[3], ix[3], iy[3];
    for (int i = 0; i < 3; ++i)
    {
      // Work on float-rounded points so the only error is the solver's.
      tx[i] = static_cast<float>(src[i].x);
      ty[i] = static_cast<float>(src[i].y);
      const cv::Point2d d = amcr::applyAffine(truth, cv::Point2d(tx[i], ty[i]));
      ix[i] = static_cast<float>(d.x);
      iy[i] = static_cast<float>(d.y);
    }
    for (int direction = 0; direction < 2; ++direction)
    {
      const bool forward = direction == 0;  // table -> image, then image -> table
      const float* sxp = forward ? tx : ix;
      const float* syp = forward ? ty : iy;
      const float* dxp = forward ? ix : tx;
      const float* dyp = forward ? iy : ty;
      const Affine& expected = forward ? truth : truth_inverse;
      float out[6] = {0, 0, 0, 0, 0, 0};
      ASSERT_TRUE(amcr::affineFromTriangles(sxp, syp, dxp, dyp, 1.f, 1.f, out)) << "trial " << tested;
      for (int i = 0; i < 3; ++i)
      {
        // Evaluated in double, so only the solver's error counts.
        const double qx = double(out[0]) * sxp[i] + double(out[1]) * syp[i] + double(out[2]);
        const double qy = double(out[3]) * sxp[i] + double(out[4]) * syp[i] + double(out[5]);
        worst_point = std::max({worst_point, std::abs(qx - dxp[i]), std::abs(qy - dyp[i])});
        EXPECT_NEAR(qx, dxp[i], 1e-3) << "trial " << tested << (forward ? " table->image" : " image->table");
        EXPECT_NEAR(qy, dyp[i], 1e-3) << "trial " << tested << (forward ? " table->image" : " image->table");
      }
      // The linear part (coefficients of order 1) to 1e-3 as well; the
      // translation is covered by the mapped points.
      for (int k : {0, 1, 3, 4})
      {
        worst_linear = std::max(worst_linear, std::abs(out[k] - expected.val[k]));
        EXPECT_NEAR(out[k], expected.val[k], 1e-3) << "trial " << tested << " coefficient " << k;
      }
    }
  }
  RecordProperty("worst_point_error_px", std::to_string(worst_point));
  RecordProperty("worst_linear_error", std::to_string(worst_linear));
}

TEST(AffineFromTriangles, RefusesCollinearAndCoincidentTriangles)
{
  const cv::Point2d good[3] = {{10, 10}, {110, 20}, {40, 90}};
  const cv::Point2d collinear[3] = {{0, 0}, {50, 50}, {100, 100}};
  const cv::Point2d nearly_collinear[3] = {{0, 0}, {50, 50.05}, {100, 100}};  // area 2.5 px^2
  const cv::Point2d coincident[3] = {{30, 40}, {30, 40}, {90, 10}};
  const cv::Point2d one_point[3] = {{30, 40}, {30, 40}, {30, 40}};
  const Affine sentinel(7, 7, 7, 7, 7, 7);

  for (const cv::Point2d* bad : {collinear, nearly_collinear, coincident, one_point})
  {
    Affine out = sentinel;
    EXPECT_FALSE(amcr::affineFromTriangles(bad, good, 20.0, out)) << "degenerate source accepted";
    EXPECT_EQ(maxAbsDiff(out, sentinel), 0.0) << "`out` changed on refusal";
    out = sentinel;
    EXPECT_FALSE(amcr::affineFromTriangles(good, bad, 20.0, out)) << "degenerate destination accepted";
    EXPECT_EQ(maxAbsDiff(out, sentinel), 0.0);

    float sx[3], sy[3], gx[3], gy[3], f[6] = {7, 7, 7, 7, 7, 7};
    for (int i = 0; i < 3; ++i)
    {
      sx[i] = static_cast<float>(bad[i].x);
      sy[i] = static_cast<float>(bad[i].y);
      gx[i] = static_cast<float>(good[i].x);
      gy[i] = static_cast<float>(good[i].y);
    }
    EXPECT_FALSE(amcr::affineFromTriangles(sx, sy, gx, gy, 20.f, 20.f, f)) << "float: degenerate source accepted";
    EXPECT_FALSE(amcr::affineFromTriangles(gx, gy, sx, sy, 20.f, 20.f, f)) << "float: degenerate destination accepted";
    for (float v : f)
      EXPECT_EQ(v, 7.f) << "float `out` changed on refusal";
  }
}

TEST(AffineFromTriangles, MinAreaIsTheThreshold)
{
  // Right triangle with legs 10 and 8: area 40 px^2 in the source; the
  // destination is the source scaled by 3 (area 360 px^2).
  const cv::Point2d src[3] = {{100, 100}, {110, 100}, {100, 108}};
  cv::Point2d dst[3];
  for (int i = 0; i < 3; ++i)
    dst[i] = src[i] * 3.0;
  Affine out;
  EXPECT_TRUE(amcr::affineFromTriangles(src, dst, 39.0, out));
  EXPECT_FALSE(amcr::affineFromTriangles(src, dst, 41.0, out)) << "source area 40 < min_area 41";
  // Swapped: the small triangle is now the destination.
  EXPECT_TRUE(amcr::affineFromTriangles(dst, src, 39.0, out));
  EXPECT_FALSE(amcr::affineFromTriangles(dst, src, 41.0, out)) << "destination area 40 < min_area 41";

  // Float overload: separate thresholds for the source and the destination.
  float sx[3], sy[3], dx[3], dy[3], f[6];
  for (int i = 0; i < 3; ++i)
  {
    sx[i] = static_cast<float>(src[i].x);
    sy[i] = static_cast<float>(src[i].y);
    dx[i] = static_cast<float>(dst[i].x);
    dy[i] = static_cast<float>(dst[i].y);
  }
  EXPECT_TRUE(amcr::affineFromTriangles(sx, sy, dx, dy, 39.f, 359.f, f));
  EXPECT_FALSE(amcr::affineFromTriangles(sx, sy, dx, dy, 41.f, 359.f, f)) << "source below min_src_area";
  EXPECT_FALSE(amcr::affineFromTriangles(sx, sy, dx, dy, 39.f, 361.f, f)) << "destination below min_dst_area";
}

TEST(AffineHelpers, ComposeWithInverseIsIdentity)
{
  std::mt19937_64 gen(5);
  for (int trial = 0; trial < 1000; ++trial)
  {
    const Affine a = randomAffine(gen);
    Affine inv;
    ASSERT_TRUE(amcr::invertAffine(a, inv));
    EXPECT_LT(maxAbsDiff(amcr::composeAffine(a, inv), amcr::identityAffine()), 1e-9) << "trial " << trial;
    EXPECT_LT(maxAbsDiff(amcr::composeAffine(inv, a), amcr::identityAffine()), 1e-9) << "trial " << trial;
    // Inverting twice gives back the original.
    Affine back;
    ASSERT_TRUE(amcr::invertAffine(inv, back));
    EXPECT_LT(maxAbsDiff(back, a), 1e-9);
  }
}

TEST(AffineHelpers, ComposeAppliesFirstThenSecond)
{
  std::mt19937_64 gen(9);
  for (int trial = 0; trial < 200; ++trial)
  {
    const Affine first = randomAffine(gen), second = randomAffine(gen);
    const Affine both = amcr::composeAffine(first, second);
    const cv::Point2d p(gen() % 640, gen() % 480);
    const cv::Point2d expected = amcr::applyAffine(second, amcr::applyAffine(first, p));
    const cv::Point2d got = amcr::applyAffine(both, p);
    EXPECT_NEAR(got.x, expected.x, 1e-9 * (1.0 + std::abs(expected.x)));
    EXPECT_NEAR(got.y, expected.y, 1e-9 * (1.0 + std::abs(expected.y)));
  }
  // Identity is neutral on both sides.
  const Affine a = randomAffine(gen);
  EXPECT_LT(maxAbsDiff(amcr::composeAffine(amcr::identityAffine(), a), a), 1e-12);
  EXPECT_LT(maxAbsDiff(amcr::composeAffine(a, amcr::identityAffine()), a), 1e-12);
}

TEST(AffineHelpers, SingularMapHasNoInverse)
{
  const Affine singular(1, 2, 5, 2, 4, 7);  // rows linearly dependent
  Affine inv(7, 7, 7, 7, 7, 7);
  EXPECT_FALSE(amcr::invertAffine(singular, inv));
  EXPECT_FALSE(amcr::invertAffine(Affine(0, 0, 1, 0, 0, 1), inv));
}

TEST(AffineHelpers, ScalesAreTheSingularValues)
{
  // R(0.7) * diag(3, 0.5) * R(-0.2): singular values 3 and 0.5.
  const double a = 0.7, b = -0.2;
  const cv::Matx22d l = cv::Matx22d(std::cos(a), -std::sin(a), std::sin(a), std::cos(a)) * cv::Matx22d(3, 0, 0, 0.5) *
                        cv::Matx22d(std::cos(b), -std::sin(b), std::sin(b), std::cos(b));
  double smallest = 0, largest = 0;
  amcr::affineScales(Affine(l(0, 0), l(0, 1), 12, l(1, 0), l(1, 1), -4), smallest, largest);
  EXPECT_NEAR(smallest, 0.5, 1e-9);
  EXPECT_NEAR(largest, 3.0, 1e-9);
}

/// A linear part R(a) diag(s1, flip * s2) R(b) with a translation, as float row-major 2x3.
void floatAffine(double a, double b, double s1, double s2, bool flip, float out[6])
{
  const cv::Matx22d l = cv::Matx22d(std::cos(a), -std::sin(a), std::sin(a), std::cos(a)) *
                        cv::Matx22d(s1, 0, 0, flip ? -s2 : s2) *
                        cv::Matx22d(std::cos(b), -std::sin(b), std::sin(b), std::cos(b));
  const double values[6] = {l(0, 0), l(0, 1), 120.0, l(1, 0), l(1, 1), -35.0};
  for (int i = 0; i < 6; ++i)
    out[i] = static_cast<float>(values[i]);
}

// The hot loop's scale check: a mirror is refused, and so is a singular
// value outside [1 / max_scale, max_scale]; decisions follow the exact
// singular values except within 1e-5 (relative) of a bound.
TEST(AffineHelpers, FloatScaleCheckRefusesMirrorsAndScalesOutOfBounds)
{
  std::mt19937_64 gen(31);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_scale(std::log(0.05), std::log(20.0)), coin(0.0, 1.0);
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 20000; ++trial)
  {
    const double s1 = std::exp(log_scale(gen)), s2 = std::exp(log_scale(gen));
    const bool flip = coin(gen) < 0.3;
    const float max_scale = trial % 2 == 0 ? 8.f : 1.5f;
    float a[6];
    const double second = angle(gen);  // one draw per statement, the last argument's first
    const double first = angle(gen);
    floatAffine(first, second, s1, s2, flip, a);
    const double largest = std::max(s1, s2), smallest = std::min(s1, s2);
    const bool expected = !flip && largest <= max_scale && smallest >= 1.0 / max_scale;
    const double margin = std::min(std::abs(largest / max_scale - 1), std::abs(smallest * max_scale - 1));
    if (margin < 1e-5)
      continue;
    EXPECT_EQ(amcr::affineScaleAccepted(a, max_scale), expected)
        << "trial " << trial << ": s " << s1 << ", " << s2 << (flip ? " mirrored" : "") << ", max_scale " << max_scale;
    (expected ? accepted : refused)++;
  }
  EXPECT_GT(accepted, 1000);
  EXPECT_GT(refused, 1000);
  // The bounds themselves are accepted: both singular values exactly 2, and 0.5.
  const float two[6] = {2, 0, 0, 0, 2, 0}, half[6] = {0.5f, 0, 0, 0, 0.5f, 0};
  EXPECT_TRUE(amcr::affineScaleAccepted(two, 2.f));
  EXPECT_TRUE(amcr::affineScaleAccepted(half, 2.f));
  const float mirror[6] = {1, 0, 0, 0, -1, 0}, singular[6] = {1, 2, 0, 2, 4, 0};
  EXPECT_FALSE(amcr::affineScaleAccepted(mirror, 2.f));
  EXPECT_FALSE(amcr::affineScaleAccepted(singular, 2.f));
}

// The float inverse equals the double one within float precision, and
// refuses a singular map without touching its output.
TEST(AffineHelpers, FloatInverseMatchesTheDoubleInverse)
{
  std::mt19937_64 gen(37);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), log_scale(std::log(0.2), std::log(5.0)), coin(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial)
  {
    float a[6], inverse[6];
    const bool flip = coin(gen) < 0.3;  // one draw per statement, the last argument's first
    const double s2 = std::exp(log_scale(gen));
    const double s1 = std::exp(log_scale(gen));
    const double second = angle(gen);
    const double first = angle(gen);
    floatAffine(first, second, s1, s2, flip, a);
    Affine exact_inverse;
    ASSERT_TRUE(amcr::invertAffine(Affine(a[0], a[1], a[2], a[3], a[4], a[5]), exact_inverse));
    ASSERT_TRUE(amcr::invertAffine(a, inverse));
    for (int i = 0; i < 6; ++i)
    {
      // Condition number up to 25: 1e-5 relative to the entry or, for a
      // translation, to the terms it sums (which may cancel).
      const double magnitude = i % 3 != 2 ? std::abs(exact_inverse.val[i])
                                          : std::abs(exact_inverse.val[i - 2] * a[2]) + std::abs(exact_inverse.val[i - 1] * a[5]);
      EXPECT_NEAR(inverse[i], exact_inverse.val[i], 1e-5 * std::max(1.0, magnitude)) << "trial " << trial << " entry " << i;
    }
  }
  const float singular[6] = {1, 2, 5, 2, 4, 7};
  float out[6] = {7, 7, 7, 7, 7, 7};
  EXPECT_FALSE(amcr::invertAffine(singular, out));
  for (float v : out)
    EXPECT_EQ(v, 7.f) << "`inverse` changed on refusal";
}
// The least-squares fit (used by the outline refinement and the ORB baseline):
// exact on noise-free points, refused where the points fix no affine.
TEST(FitAffine, RecoversRandomAffinesFromManyPoints)
{
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> x(0.0, 639.0), y(0.0, 479.0);
  for (int trial = 0; trial < 200; ++trial)
  {
    const Affine truth = randomAffine(gen);
    std::vector<cv::Point2d> from, to;
    for (int i = 0; i < 3 + trial % 20; ++i)
    {
      const double from_y = y(gen);  // one draw per statement: a call's arguments come in no set order
      from.emplace_back(x(gen), from_y);
      to.push_back(amcr::applyAffine(truth, from.back()));
    }
    Affine fitted;
    if (std::abs(twiceArea(from.data())) < 2.0 * 500.0)
      continue;  // three nearly collinear points: not a test of the fit
    ASSERT_TRUE(amcr::fitAffine(from, to, fitted)) << "trial " << trial;
    EXPECT_LT(maxAbsDiff(fitted, truth), 1e-6) << "trial " << trial;
  }
}

TEST(FitAffine, RefusesTooFewCollinearOrMismatchedPoints)
{
  Affine out = amcr::identityAffine();
  const std::vector<cv::Point2d> two = {{0, 0}, {10, 0}};
  EXPECT_FALSE(amcr::fitAffine(two, two, out));
  const std::vector<cv::Point2d> line = {{0, 0}, {10, 10}, {20, 20}, {30, 30}};
  EXPECT_FALSE(amcr::fitAffine(line, line, out));
  const std::vector<cv::Point2d> three = {{0, 0}, {10, 0}, {0, 10}};
  EXPECT_FALSE(amcr::fitAffine(three, line, out));
}
}  // namespace
