// Systematic resampling (paper 3.6, Thrun et al. table 4.4): unbiased, low
// variance, robust to zero weights, the log version equal to the linear one.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/random.h"
#include "amcr/filter/resampling.h"

namespace
{
std::vector<double> randomWeights(int n, amcr::Rng& rng)
{
  std::vector<double> w(n);
  for (double& x : w)
    x = std::pow(rng.uniform(), 3.0);  // skewed: many small, a few large
  w[n / 2] = 0.0;                      // and a zero that must never be drawn
  return w;
}

std::vector<int> counts(const std::vector<int>& indices, int n)
{
  std::vector<int> c(n, 0);
  for (int i : indices)
  {
    EXPECT_GE(i, 0);
    EXPECT_LT(i, n);
    if (i >= 0 && i < n)
      ++c[i];
  }
  return c;
}

TEST(SystematicResample, OutputSizeIsCount)
{
  amcr::Rng rng(1);
  const std::vector<double> w = randomWeights(100, rng);
  for (int count : {1, 7, 100, 1000})
  {
    EXPECT_EQ(amcr::systematicResample(w, count, rng).size(), static_cast<std::size_t>(count));
    std::vector<double> lw(w.size());
    std::transform(w.begin(), w.end(), lw.begin(), [](double x) { return std::log(x); });
    EXPECT_EQ(amcr::systematicResampleLog(lw, count, rng).size(), static_cast<std::size_t>(count));
  }
}

// Unbiased: E[copies of i] = count * w_i / sum(w). Systematic resampling
// gives each index floor or ceil of count * w_i copies, so the copies of one
// index per draw have a variance of at most 1/4, and the mean over D draws of
// copies / count has a standard deviation of at most 0.5 / (count sqrt(D)).
// Bound: 5 of those standard deviations (a false alarm has p < 1e-6 per index).
TEST(SystematicResample, IsUnbiased)
{
  amcr::Rng rng(42);
  const int n = 20, count = 50, draws = 20000;
  const std::vector<double> w = randomWeights(n, rng);
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  std::vector<long> sum(n, 0);
  for (int d = 0; d < draws; ++d)
  {
    const std::vector<int> c = counts(amcr::systematicResample(w, count, rng), n);
    for (int i = 0; i < n; ++i)
      sum[i] += c[i];
  }
  const double bound = 5.0 * 0.5 / (count * std::sqrt(static_cast<double>(draws)));  // 3.5e-4
  for (int i = 0; i < n; ++i)
  {
    const double share = static_cast<double>(sum[i]) / (static_cast<double>(draws) * count);
    EXPECT_NEAR(share, w[i] / total, bound) << "index " << i;
  }
  EXPECT_EQ(sum[n / 2], 0) << "a zero weight was drawn";
}

// Low variance, the property that makes it systematic and not multinomial:
// every draw gives index i floor(count * p_i) or ceil(count * p_i) copies.
TEST(SystematicResample, CopiesAreFloorOrCeilOfExpected)
{
  amcr::Rng rng(7);
  for (int trial = 0; trial < 500; ++trial)
  {
    const int n = 1 + static_cast<int>(rng.index(40));
    const int count = 1 + static_cast<int>(rng.index(200));
    std::vector<double> w = randomWeights(n, rng);
    if (n == 1)
      w[0] = 1.0;
    const double total = std::accumulate(w.begin(), w.end(), 0.0);
    const std::vector<int> c = counts(amcr::systematicResample(w, count, rng), n);
    for (int i = 0; i < n; ++i)
    {
      const double expected = count * w[i] / total;
      // 1e-9 slack for expected values that are integers up to rounding.
      EXPECT_GE(c[i], std::floor(expected - 1e-9)) << "trial " << trial << " index " << i;
      EXPECT_LE(c[i], std::ceil(expected + 1e-9)) << "trial " << trial << " index " << i;
    }
  }
}

// Every weight zero (or not finite): a uniform draw, not a division by zero.
TEST(SystematicResample, DegenerateWeightsGiveAUniformDraw)
{
  amcr::Rng rng(3);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<double>> cases = {
      std::vector<double>(10, 0.0), std::vector<double>(10, nan), {0, nan, 0, 0, nan, 0, 0, 0, 0, 0}};
  for (const auto& w : cases)
  {
    const std::vector<int> c = counts(amcr::systematicResample(w, 40, rng), 10);
    for (int i = 0; i < 10; ++i)
      EXPECT_EQ(c[i], 4) << "uniform over 10 indices, 40 draws: 4 each (index " << i << ")";
  }
  // Log version: every log-weight -inf (all weights zero) or NaN.
  for (double v : {-inf, nan})
  {
    const std::vector<int> c = counts(amcr::systematicResampleLog(std::vector<double>(10, v), 40, rng), 10);
    for (int i = 0; i < 10; ++i)
      EXPECT_EQ(c[i], 4) << "log-weight " << v << " index " << i;
  }
}

// A single non-finite weight among good ones is never drawn and does not
// poison the others.
TEST(SystematicResample, OneInfiniteLogWeightIsIgnored)
{
  amcr::Rng rng(4);
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> lw = {0.0, -inf, std::log(3.0)};  // weights 1, 0, 3
  const std::vector<int> c = counts(amcr::systematicResampleLog(lw, 40, rng), 3);
  EXPECT_EQ(c[0], 10);
  EXPECT_EQ(c[1], 0);
  EXPECT_EQ(c[2], 30);
}

// The log version, with any constant added to every log-weight (it is
// max-subtracted), equals the linear version with the same generator state.
TEST(SystematicResample, LogVersionEqualsLinear)
{
  amcr::Rng weights_rng(11);
  for (int trial = 0; trial < 200; ++trial)
  {
    const int n = 2 + static_cast<int>(weights_rng.index(60));
    const std::vector<double> w = randomWeights(n, weights_rng);
    const double shift = weights_rng.uniform(-700.0, 700.0);
    std::vector<double> lw(n);
    for (int i = 0; i < n; ++i)
      lw[i] = std::log(w[i]) + shift;  // log(0) = -inf for the zero weight
    amcr::Rng a(1000 + trial), b(1000 + trial);
    const std::vector<int> linear = amcr::systematicResample(w, 3 * n, a);
    const std::vector<int> logs = amcr::systematicResampleLog(lw, 3 * n, b);
    EXPECT_EQ(linear, logs) << "trial " << trial << " shift " << shift;
  }
}

// Very negative log-weights (e.g. 8 rays of tiny likelihood) must not all
// underflow to zero: they are max-subtracted first.
TEST(SystematicResample, LogVersionSurvivesUnderflow)
{
  amcr::Rng rng(5);
  const std::vector<double> lw = {-2000.0, -2000.0 + std::log(3.0), -3000.0};  // weights 1 : 3 : ~0
  const std::vector<int> c = counts(amcr::systematicResampleLog(lw, 400, rng), 3);
  EXPECT_EQ(c[0], 100);
  EXPECT_EQ(c[1], 300);
  EXPECT_EQ(c[2], 0);
}

TEST(SystematicResample, SameSeedSameDraw)
{
  amcr::Rng w_rng(6);
  const std::vector<double> w = randomWeights(30, w_rng);
  amcr::Rng a(99), b(99);
  for (int k = 0; k < 20; ++k)
    EXPECT_EQ(amcr::systematicResample(w, 30, a), amcr::systematicResample(w, 30, b));
}
}  // namespace
