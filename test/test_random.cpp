// The random generators (random.h): reproducible, independent streams, and
// a normal sampler with the right distribution (moments and a
// Kolmogorov-Smirnov test at fixed seeds).
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/random.h"

namespace
{
std::vector<double> uniforms(amcr::Rng& rng, int n)
{
  std::vector<double> draws(n);
  for (double& d : draws)
    d = rng.uniform();
  return draws;
}

/// The Kolmogorov-Smirnov statistic of `draws` against the CDF `cdf`.
template <typename Cdf>
double ksStatistic(std::vector<double> draws, Cdf cdf)
{
  std::sort(draws.begin(), draws.end());
  const double n = static_cast<double>(draws.size());
  double d = 0.0;
  for (std::size_t i = 0; i < draws.size(); ++i)
  {
    const double f = cdf(draws[i]);
    d = std::max({d, f - i / n, (i + 1) / n - f});
  }
  return d;
}

// The critical value of the KS statistic at significance 0.001 for n draws.
double ksCritical(std::size_t n) { return 1.95 / std::sqrt(static_cast<double>(n)); }

TEST(Rng, SameSeedSameDraws)
{
  amcr::Rng a(42), b(42), c(43);
  const std::vector<double> da = uniforms(a, 100), db = uniforms(b, 100), dc = uniforms(c, 100);
  EXPECT_EQ(da, db);
  EXPECT_NE(da, dc);
}

TEST(Rng, StreamsAreReproducibleAndDistinct)
{
  std::vector<amcr::Rng> few = amcr::Rng::streams(7, 3);
  std::vector<amcr::Rng> many = amcr::Rng::streams(7, 50);
  ASSERT_EQ(few.size(), 3u);
  ASSERT_EQ(many.size(), 50u);
  // Stream k does not depend on how many streams were made.
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(uniforms(few[k], 20), uniforms(many[k], 20)) << "stream " << k;
  // No two streams, and no stream and the seed's own generator, start alike.
  amcr::Rng base(7);
  std::vector<std::vector<double>> starts;
  starts.push_back(uniforms(base, 4));
  for (int k = 3; k < 50; ++k)
    starts.push_back(uniforms(many[k], 4));
  std::sort(starts.begin(), starts.end());
  EXPECT_EQ(std::adjacent_find(starts.begin(), starts.end()), starts.end());
}

TEST(Rng, UniformIsUniform)
{
  amcr::Rng rng(3);
  const std::vector<double> draws = uniforms(rng, 100000);
  EXPECT_GE(*std::min_element(draws.begin(), draws.end()), 0.0);
  EXPECT_LT(*std::max_element(draws.begin(), draws.end()), 1.0);
  EXPECT_LT(ksStatistic(draws, [](double x) { return x; }), ksCritical(draws.size()));
  for (int k = 0; k < 1000; ++k)
  {
    const double x = rng.uniform(-2.0, 5.0);
    ASSERT_GE(x, -2.0);
    ASSERT_LT(x, 5.0);
  }
}

TEST(Rng, IndexIsUnbiased)
{
  amcr::Rng rng(5);
  const int n = 7, draws = 70000;
  std::vector<int> counts(n, 0);
  for (int k = 0; k < draws; ++k)
  {
    const std::size_t i = rng.index(n);
    ASSERT_LT(i, static_cast<std::size_t>(n));
    ++counts[i];
  }
  double chi2 = 0.0;
  const double expected = static_cast<double>(draws) / n;
  for (int c : counts)
    chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 22.46);  // chi-square, 6 degrees of freedom, p = 0.001
  EXPECT_EQ(rng.index(1), 0u);
}

TEST(Rng, GaussianHasTheNormalMomentsAndDistribution)
{
  for (std::uint64_t seed : {1u, 2u})
  {
    amcr::Rng rng(seed);
    const int n = 200000;
    std::vector<double> draws(n);
    double sum = 0, sum2 = 0, sum3 = 0, sum4 = 0;
    for (double& d : draws)
    {
      d = rng.gaussian(1.0);
      sum += d;
      sum2 += d * d;
      sum3 += d * d * d;
      sum4 += d * d * d * d;
    }
    // Standard errors at n = 2e5: mean 0.0022, variance 0.0032, skewness
    // 0.0055, kurtosis 0.011; the bounds are about 5 of them.
    const double mean = sum / n;
    const double variance = sum2 / n - mean * mean;
    EXPECT_NEAR(mean, 0.0, 0.011) << "seed " << seed;
    EXPECT_NEAR(variance, 1.0, 0.016) << "seed " << seed;
    EXPECT_NEAR(sum3 / n, 0.0, 0.03) << "seed " << seed;
    EXPECT_NEAR(sum4 / n, 3.0, 0.06) << "seed " << seed;
    const double d = ksStatistic(draws, [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); });
    EXPECT_LT(d, ksCritical(draws.size())) << "seed " << seed;
  }
}

TEST(Rng, GaussianScalesBySigma)
{
  amcr::Rng a(9), b(9);
  for (int k = 0; k < 100; ++k)
    EXPECT_DOUBLE_EQ(a.gaussian(2.5), 2.5 * b.gaussian(1.0));
  EXPECT_EQ(a.gaussian(0.0), 0.0);
}
}  // namespace
