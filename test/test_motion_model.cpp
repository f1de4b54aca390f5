// The motion model Q (paper 4.2): an M-particle repeats its V-particle's
// move mapped through its own A (input -> prototype), plus Gaussian noise.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/motion_model.h"
#include "amcr/filter/particles.h"
#include "amcr/base/random.h"
#include "amcr/scan/ray_directions.h"

namespace
{
const std::vector<amcr::Control> kControls = {
    {0.0, 5.0}, {0.4, 3.0}, {-1.2, 7.5}, {M_PI / 2, 0.0}, {3.0, 2.0}, {-3.1, 10.0}, {0.05, 0.5}};

// n M-particles at distinct poses, all with affine `a` (row-major 2x3) and
// heading `theta` (or spread headings when theta is NaN).
amcr::MParticleSet makeM(int n, const float a[6], bool valid, float theta)
{
  amcr::MParticleSet m;
  m.resize(n);
  for (int i = 0; i < n; ++i)
  {
    m.x[i] = 20.f + 7.f * (i % 20);
    m.y[i] = 90.f - 3.f * (i % 20);
    m.theta[i] = std::isnan(theta) ? -3.f + 0.9f * (i % 7) : theta;
    m.prototype[i] = i % 3;
    for (int k = 0; k < 6; ++k)
      m.affine[k][i] = a[k];
    m.affine_valid[i] = valid ? 1 : 0;
    m.log_likelihood[i] = -1.f;
  }
  return m;
}

TEST(MotionModel, MoveVTurnsThenMovesForward)
{
  amcr::VParticle v;
  v.x = 100.f;
  v.y = 50.f;
  v.theta = 0.5f;
  amcr::MotionModel::moveV(v, {0.3, 10.0});
  EXPECT_NEAR(v.theta, 0.8, 1e-6);
  EXPECT_NEAR(v.x, 100.0 + 10.0 * std::cos(0.8), 1e-4);
  EXPECT_NEAR(v.y, 50.0 + 10.0 * std::sin(0.8), 1e-4);
}

// A = identity, no noise: every M-particle makes its V-particle's move,
// whatever its own position and heading.
TEST(MotionModel, IdentityAffineWithoutNoiseCopiesTheVMove)
{
  const float identity[6] = {1, 0, 0, 0, 1, 0};
  const amcr::MotionModel model(0.0, 0.0);
  amcr::Rng rng(1);
  for (float v_theta : {0.3f, -2.0f, 3.1f})
    for (const amcr::Control& u : kControls)
    {
      amcr::VParticle v;
      v.x = 200.f;
      v.y = 150.f;
      v.theta = v_theta;
      const amcr::VParticle before = v;
      amcr::MotionModel::moveV(v, u);

      for (float m_theta : {v_theta, std::nanf("")})  // aligned with V, and spread headings
      {
        amcr::MParticleSet m = makeM(8, identity, true, m_theta);
        const amcr::MParticleSet m0 = m;
        model.moveM(m, 0, m.size(), before.theta, u, rng);
        for (std::size_t i = 0; i < m.size(); ++i)
        {
          SCOPED_TRACE("control (" + std::to_string(u.rotation) + ", " + std::to_string(u.translation) +
                       ") particle " + std::to_string(i));
          EXPECT_NEAR(m.x[i] - m0.x[i], v.x - before.x, 1e-4);
          EXPECT_NEAR(m.y[i] - m0.y[i], v.y - before.y, 1e-4);
          EXPECT_NEAR(amcr::wrapAngle(m.theta[i] - m0.theta[i]), amcr::wrapAngle(v.theta - before.theta), 1e-5);
          EXPECT_EQ(m.prototype[i], m0.prototype[i]);
          EXPECT_EQ(m.affine_valid[i], m0.affine_valid[i]);
        }
      }
    }
}

// Only [begin, end) moves.
TEST(MotionModel, MovesOnlyTheGivenRange)
{
  const float identity[6] = {1, 0, 0, 0, 1, 0};
  amcr::MParticleSet m = makeM(10, identity, true, 0.f);
  const amcr::MParticleSet m0 = m;
  amcr::Rng rng(2);
  amcr::MotionModel(1.0, 0.1).moveM(m, 3, 7, 0.0, {0.2, 5.0}, rng);
  for (std::size_t i = 0; i < m.size(); ++i)
  {
    const bool inside = i >= 3 && i < 7;
    EXPECT_EQ(m.x[i] != m0.x[i], inside) << "particle " << i;
    EXPECT_EQ(m.theta[i] != m0.theta[i], inside) << "particle " << i;
  }
}

// A = s R(phi) (+ any translation): the displacement is s R(phi) times the V
// displacement, and the heading turns by the V's turn (a similarity keeps angles).
TEST(MotionModel, RotationScaleAffineMapsTheDisplacement)
{
  const amcr::MotionModel model(0.0, 0.0);
  amcr::Rng rng(3);
  for (double phi : {0.0, 0.7, -2.5})
    for (double s : {0.5, 1.0, 2.2})
    {
      const float a[6] = {static_cast<float>(s * std::cos(phi)), static_cast<float>(-s * std::sin(phi)), 13.f,
                          static_cast<float>(s * std::sin(phi)), static_cast<float>(s * std::cos(phi)), -41.f};
      for (const amcr::Control& u : kControls)
      {
        amcr::VParticle v;
        v.x = 300.f;
        v.y = 200.f;
        v.theta = 1.1f;
        const amcr::VParticle before = v;
        amcr::MotionModel::moveV(v, u);
        const double dvx = v.x - before.x, dvy = v.y - before.y;
        // M headings consistent with A: the V heading mapped by A.
        amcr::MParticleSet m = makeM(5, a, true, static_cast<float>(before.theta + phi));
        const amcr::MParticleSet m0 = m;
        model.moveM(m, 0, m.size(), before.theta, u, rng);
        for (std::size_t i = 0; i < m.size(); ++i)
        {
          SCOPED_TRACE("phi " + std::to_string(phi) + " s " + std::to_string(s) + " control (" +
                       std::to_string(u.rotation) + ", " + std::to_string(u.translation) + ")");
          EXPECT_NEAR(m.x[i] - m0.x[i], a[0] * dvx + a[1] * dvy, 1e-3);
          EXPECT_NEAR(m.y[i] - m0.y[i], a[3] * dvx + a[4] * dvy, 1e-3);
          EXPECT_NEAR(amcr::wrapAngle(m.theta[i] - m0.theta[i]), amcr::wrapAngle(u.rotation), 1e-4);
        }
      }
    }
}

// A general affine (with shear): the displacement is still the linear part
// times the V displacement.
TEST(MotionModel, ShearedAffineMapsTheDisplacement)
{
  const float a[6] = {1.3f, 0.4f, 5.f, -0.2f, 0.7f, 9.f};
  amcr::Rng rng(4);
  for (const amcr::Control& u : kControls)
  {
    amcr::VParticle v;
    v.theta = -0.6f;
    const amcr::VParticle before = v;
    amcr::MotionModel::moveV(v, u);
    const double dvx = v.x - before.x, dvy = v.y - before.y;
    amcr::MParticleSet m = makeM(4, a, true, 0.f);
    const amcr::MParticleSet m0 = m;
    amcr::MotionModel(0.0, 0.0).moveM(m, 0, m.size(), before.theta, u, rng);
    for (std::size_t i = 0; i < m.size(); ++i)
    {
      EXPECT_NEAR(m.x[i] - m0.x[i], a[0] * dvx + a[1] * dvy, 1e-3);
      EXPECT_NEAR(m.y[i] - m0.y[i], a[3] * dvx + a[4] * dvy, 1e-3);
    }
  }
}

// No valid A: the move is rotated by the angle from the V heading to the M
// heading (motion_model.h), without scaling.
TEST(MotionModel, WithoutAffineTheMoveIsRotatedOntoTheMHeading)
{
  const float junk[6] = {9, 9, 9, 9, 9, 9};  // must be ignored
  amcr::Rng rng(5);
  for (const amcr::Control& u : kControls)
  {
    amcr::VParticle v;
    v.theta = 0.4f;
    const amcr::VParticle before = v;
    amcr::MotionModel::moveV(v, u);
    const double dvx = v.x - before.x, dvy = v.y - before.y;
    amcr::MParticleSet m = makeM(7, junk, false, std::nanf(""));
    const amcr::MParticleSet m0 = m;
    amcr::MotionModel(0.0, 0.0).moveM(m, 0, m.size(), before.theta, u, rng);
    for (std::size_t i = 0; i < m.size(); ++i)
    {
      const double r = m0.theta[i] - before.theta;
      EXPECT_NEAR(m.x[i] - m0.x[i], std::cos(r) * dvx - std::sin(r) * dvy, 1e-3) << "particle " << i;
      EXPECT_NEAR(m.y[i] - m0.y[i], std::sin(r) * dvx + std::cos(r) * dvy, 1e-3) << "particle " << i;
      EXPECT_NEAR(amcr::wrapAngle(m.theta[i] - m0.theta[i]), amcr::wrapAngle(u.rotation), 1e-4);
    }
  }
}

// With noise: over N moves the deviation from the noise-free move has mean 0
// and standard deviation sigma_t in x and in y, sigma_r in heading.
// Bounds (N = 40000): mean within 5 sigma / sqrt(N) = 0.025 sigma; the sample
// standard deviation has a relative standard error of 1 / sqrt(2N) = 0.35%,
// so within 2% (about 5.7 standard errors).
TEST(MotionModel, NoiseHasTheConfiguredSigmas)
{
  const int n = 40000;
  const double sigma_t = 1.5, sigma_r = 0.08;
  const float a[6] = {0.8f, -0.3f, 0.f, 0.3f, 0.8f, 0.f};
  const amcr::Control u{0.25, 6.0};
  const double v_theta = 0.9;
  const double h = v_theta + u.rotation;
  const double ex = 6.0 * (a[0] * std::cos(h) + a[1] * std::sin(h));
  const double ey = 6.0 * (a[3] * std::cos(h) + a[4] * std::sin(h));

  amcr::MParticleSet m = makeM(n, a, true, static_cast<float>(v_theta + std::atan2(0.3, 0.8)));
  const amcr::MParticleSet m0 = m;
  amcr::Rng rng(6);
  amcr::MotionModel(sigma_t, sigma_r).moveM(m, 0, m.size(), v_theta, u, rng);

  double sx = 0, sy = 0, st = 0, sxx = 0, syy = 0, stt = 0;
  for (int i = 0; i < n; ++i)
  {
    const double dx = m.x[i] - m0.x[i] - ex;
    const double dy = m.y[i] - m0.y[i] - ey;
    const double dt = amcr::wrapAngle(m.theta[i] - m0.theta[i] - u.rotation);
    sx += dx;
    sy += dy;
    st += dt;
    sxx += dx * dx;
    syy += dy * dy;
    stt += dt * dt;
  }
  const auto stdev = [n](double s, double ss) { return std::sqrt(ss / n - (s / n) * (s / n)); };
  EXPECT_NEAR(sx / n, 0.0, 5.0 * sigma_t / std::sqrt(n));
  EXPECT_NEAR(sy / n, 0.0, 5.0 * sigma_t / std::sqrt(n));
  EXPECT_NEAR(st / n, 0.0, 5.0 * sigma_r / std::sqrt(n));
  EXPECT_NEAR(stdev(sx, sxx), sigma_t, 0.02 * sigma_t);
  EXPECT_NEAR(stdev(sy, syy), sigma_t, 0.02 * sigma_t);
  EXPECT_NEAR(stdev(st, stt), sigma_r, 0.02 * sigma_r);
}

TEST(MotionModel, ReadsItsSigmasFromParams)
{
  amcr::Params p;
  p.motion_noise_translation = 0.0;
  p.motion_noise_rotation = 0.0;
  const float identity[6] = {1, 0, 0, 0, 1, 0};
  amcr::MParticleSet m = makeM(50, identity, true, 0.f);
  const amcr::MParticleSet m0 = m;
  amcr::Rng rng(8);
  amcr::MotionModel(p).moveM(m, 0, m.size(), 0.0, {0.0, 2.0}, rng);
  for (std::size_t i = 0; i < m.size(); ++i)
  {
    EXPECT_NEAR(m.x[i] - m0.x[i], 2.0, 1e-5);
    EXPECT_NEAR(m.y[i] - m0.y[i], 0.0, 1e-5);
  }
  p.motion_noise_translation = 2.0;
  m = m0;
  amcr::MotionModel(p).moveM(m, 0, m.size(), 0.0, {0.0, 2.0}, rng);
  int moved_off_line = 0;
  for (std::size_t i = 0; i < m.size(); ++i)
    moved_off_line += std::abs(m.y[i] - m0.y[i]) > 1e-3;
  EXPECT_GT(moved_off_line, 40) << "translation noise from Params not applied";
}
}  // namespace
