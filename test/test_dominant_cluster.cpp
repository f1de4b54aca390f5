// The densest M-cluster of a V-particle (spec "Output"): the mode with the
// most members over all prototypes, not the mean shift inside whichever
// prototype happens to hold the most particles.
#include <cstdint>
#include <initializer_list>

#include <gtest/gtest.h>

#include "amcr/extraction/object_extraction.h"
#include "amcr/base/random.h"

namespace
{
constexpr double kRadius = 6.0;        // table px, the default cluster_radius
constexpr double kMeanTolerance = 1.0;  // table px
constexpr int kPrototypes = 4;

/// `count` particles of `prototype`, uniform within +-`spread` table px of
/// `centre`, with log likelihood `log_likelihood`.
struct Placement
{
  int count;
  int prototype;
  cv::Point2f centre;
  float spread;
  float log_likelihood;
};

/// An M-particle set of the placements in order, drawn with `seed`.
amcr::MParticleSet particles(std::uint64_t seed, std::initializer_list<Placement> placements)
{
  std::size_t n = 0;
  for (const Placement& p : placements)
    n += static_cast<std::size_t>(p.count);
  amcr::MParticleSet m;
  m.resize(n);
  amcr::Rng rng(seed);
  std::size_t k = 0;
  for (const Placement& p : placements)
    for (int i = 0; i < p.count; ++i, ++k)
    {
      m.prototype[k] = p.prototype;
      m.x[k] = p.centre.x + static_cast<float>(rng.uniform(-p.spread, p.spread));
      m.y[k] = p.centre.y + static_cast<float>(rng.uniform(-p.spread, p.spread));
      m.theta[k] = 0.f;
      m.log_likelihood[k] = p.log_likelihood;
      m.affine_valid[k] = amcr::kNoAffine;
    }
  return m;
}

/// Expects the cluster of `prototype` at `mean` holding `share` of the particles.
void expectCluster(const amcr::VParticleCluster& c, int prototype, cv::Point2f mean, float share, float share_tolerance)
{
  EXPECT_EQ(c.prototype, prototype);
  EXPECT_NEAR(c.mean.x, mean.x, kMeanTolerance);
  EXPECT_NEAR(c.mean.y, mean.y, kMeanTolerance);
  EXPECT_NEAR(c.share, share, share_tolerance);
}

TEST(DominantCluster, ATightClusterWinsOverMoreParticlesSpreadInAnotherPrototype)
{
  // Prototype 0 holds the most particles (45), spread over its whole table;
  // prototype 2 holds 35, 30 of them within 2 px of one place.
  const amcr::MParticleSet m = particles(7, {{45, 0, {64, 64}, 60.f, -12.f},
                                             {30, 2, {40, 90}, 2.f, -8.f},
                                             {5, 2, {100, 20}, 10.f, -12.f},
                                             {20, 1, {64, 64}, 60.f, -12.f}});
  expectCluster(amcr::dominantCluster(m, 0, 100, kPrototypes, kRadius), 2, {40, 90}, 0.30f, 0.011f);
}

TEST(DominantCluster, TheMostPopulatedPrototypeWinsWhenItHoldsTheDensestMode)
{
  const amcr::MParticleSet m = particles(8, {{40, 1, {30, 30}, 2.f, -8.f}, {20, 3, {90, 90}, 2.f, -9.f}});
  expectCluster(amcr::dominantCluster(m, 0, 60, kPrototypes, kRadius), 1, {30, 30}, 40.f / 60.f, 1e-6f);
}

TEST(DominantCluster, OnlyTheGivenRangeCounts)
{
  const amcr::MParticleSet m = particles(9, {{40, 0, {20, 20}, 2.f, -8.f},    // another V-particle's
                                             {10, 1, {70, 70}, 2.f, -8.f},    // this one's: 10 together
                                             {30, 2, {64, 64}, 60.f, -9.f}});  // and 30 spread
  expectCluster(amcr::dominantCluster(m, 40, 80, kPrototypes, kRadius), 1, {70, 70}, 10.f / 40.f, 1e-6f);
}

/// Gives the particles [first, last) of `m` the fitted affine `a` (image -> table).
void fit(amcr::MParticleSet& m, std::size_t first, std::size_t last, const amcr::Affine& a)
{
  for (std::size_t i = first; i < last; ++i)
  {
    for (int e = 0; e < 6; ++e)
      m.affine[e][i] = static_cast<float>(a(e / 3, e % 3));
    m.affine_valid[i] = amcr::kFittedAffine;
  }
}

TEST(DominantCluster, TheLikeliestModeIsTheMostLikelyParticlesOwn)
{
  // Prototype 0 holds the densest mode (40 together, less likely); prototype
  // 3 a loose one of 8 about its most likely particle (-7 against -9).
  amcr::MParticleSet m = particles(10, {{40, 0, {30, 30}, 2.f, -9.f},
                                        {1, 3, {80, 50}, 0.f, -7.f},
                                        {7, 3, {80, 50}, 3.f, -8.f},
                                        {12, 1, {64, 64}, 60.f, -10.f}});
  const amcr::Affine a(0.5, 0.0, 10.0, 0.0, 0.5, 20.0), b(0.6, 0.1, 8.0, -0.1, 0.6, 22.0);
  fit(m, 0, 40, b);
  fit(m, 40, 48, a);
  const amcr::VParticleCluster c = amcr::dominantCluster(m, 0, 60, kPrototypes, kRadius, true);
  expectCluster(c, 0, {30, 30}, 40.f / 60.f, 1e-6f);
  EXPECT_EQ(c.likeliest.prototype, 3);
  EXPECT_FLOAT_EQ(c.likeliest.log_likelihood, -7.f);
  EXPECT_NEAR(c.likeliest.mean.x, 80.f, 1.5f);
  EXPECT_NEAR(c.likeliest.mean.y, 50.f, 1.5f);
  ASSERT_TRUE(c.likeliest.has_affine);
  // The mean A of the mode's particles with an A: 8 of them, all at `a`.
  EXPECT_LT(cv::norm(cv::Matx<double, 2, 3>(c.likeliest.image_to_table - a)), 1e-5);
}

TEST(DominantCluster, NoLikeliestModeWithoutAFittedAffine)
{
  const amcr::MParticleSet m = particles(11, {{20, 1, {30, 30}, 2.f, -8.f}});
  EXPECT_EQ(amcr::dominantCluster(m, 0, 20, kPrototypes, kRadius, true).likeliest.prototype, -1);
}

TEST(DominantCluster, AnEmptyRangeHasNoCluster)
{
  amcr::MParticleSet m;
  m.resize(10);
  const amcr::VParticleCluster c = amcr::dominantCluster(m, 5, 5, kPrototypes, kRadius);
  EXPECT_EQ(c.prototype, -1);
  EXPECT_EQ(c.share, 0.f);
}
}  // namespace
