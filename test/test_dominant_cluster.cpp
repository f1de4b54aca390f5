// The densest M-cluster of a V-particle (spec "Output"): the mode with the
// most members over all prototypes, not the mean shift inside whichever
// prototype happens to hold the most particles.
#include <gtest/gtest.h>

#include "amcr/object_extraction.h"
#include "amcr/random.h"

namespace
{
constexpr double kRadius = 6.0;        // table px, the default cluster_radius
constexpr double kMeanTolerance = 1.0;  // table px
constexpr int kPrototypes = 4;

/// `count` particles of `prototype` from index `begin`: around `centre` within
/// +-`spread` table px (uniform), with log likelihood `log_likelihood`.
void place(amcr::MParticleSet& m, std::size_t begin, int count, int prototype, cv::Point2f centre, float spread,
           float log_likelihood, amcr::Rng& rng)
{
  for (int i = 0; i < count; ++i)
  {
    const std::size_t k = begin + static_cast<std::size_t>(i);
    m.prototype[k] = prototype;
    m.x[k] = centre.x + static_cast<float>(rng.uniform(-spread, spread));
    m.y[k] = centre.y + static_cast<float>(rng.uniform(-spread, spread));
    m.theta[k] = 0.f;
    m.log_likelihood[k] = log_likelihood;
    m.affine_valid[k] = amcr::kNoAffine;
  }
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
  amcr::Rng rng(7);
  amcr::MParticleSet m;
  m.resize(100);
  // Prototype 0 holds the most particles (45), spread over its whole table;
  // prototype 2 holds 35, 30 of them within 2 px of one place.
  place(m, 0, 45, 0, {64, 64}, 60.f, -12.f, rng);
  place(m, 45, 30, 2, {40, 90}, 2.f, -8.f, rng);
  place(m, 75, 5, 2, {100, 20}, 10.f, -12.f, rng);
  place(m, 80, 20, 1, {64, 64}, 60.f, -12.f, rng);

  expectCluster(amcr::dominantCluster(m, 0, 100, kPrototypes, kRadius), 2, {40, 90}, 0.30f, 0.011f);
}

TEST(DominantCluster, TheMostPopulatedPrototypeWinsWhenItHoldsTheDensestMode)
{
  amcr::Rng rng(8);
  amcr::MParticleSet m;
  m.resize(60);
  place(m, 0, 40, 1, {30, 30}, 2.f, -8.f, rng);
  place(m, 40, 20, 3, {90, 90}, 2.f, -9.f, rng);

  expectCluster(amcr::dominantCluster(m, 0, 60, kPrototypes, kRadius), 1, {30, 30}, 40.f / 60.f, 1e-6f);
}

TEST(DominantCluster, OnlyTheGivenRangeCounts)
{
  amcr::Rng rng(9);
  amcr::MParticleSet m;
  m.resize(80);
  place(m, 0, 40, 0, {20, 20}, 2.f, -8.f, rng);   // another V-particle's
  place(m, 40, 10, 1, {70, 70}, 2.f, -8.f, rng);  // this one's: 10 together
  place(m, 50, 30, 2, {64, 64}, 60.f, -9.f, rng);  // and 30 spread

  const amcr::VParticleCluster c = amcr::dominantCluster(m, 40, 80, kPrototypes, kRadius);
  EXPECT_EQ(c.prototype, 1);
  EXPECT_NEAR(c.share, 10.f / 40.f, 1e-6f);
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
