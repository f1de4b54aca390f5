// parallelFor (parallel_for.h): every index once, whatever the thread
// count, and an exception of the lowest failing index passed on.
#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/parallel_for.h"

namespace
{
TEST(ParallelFor, RunsEveryIndexOnce)
{
  for (int threads : {1, 2, 4, 9})
    for (int count : {0, 1, 3, 100})
    {
      std::vector<std::atomic<int>> runs(count);
      amcr::parallelFor(count, threads, [&](int i) { ++runs[i]; });
      for (int i = 0; i < count; ++i)
        EXPECT_EQ(runs[i].load(), 1) << "index " << i << " of " << count << " on " << threads << " threads";
    }
}

TEST(ParallelFor, PassesOnTheLowestIndexsExceptionAfterRunningTheRest)
{
  for (int threads : {1, 2, 4})
  {
    std::vector<std::atomic<int>> runs(40);
    try
    {
      amcr::parallelFor(40, threads, [&](int i) {
        ++runs[i];
        if (i == 9 || i == 31)
          throw std::runtime_error("piece " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception on " << threads << " threads";
    }
    catch (const std::runtime_error& e)
    {
      EXPECT_EQ(std::string(e.what()), "piece 9") << threads << " threads";
    }
    for (int i = 0; i < 40; ++i)
      EXPECT_EQ(runs[i].load(), 1) << "index " << i << " on " << threads << " threads";
  }
}

TEST(ParallelFor, ZeroThreadsMeansEveryCore)
{
  EXPECT_GE(amcr::resolveThreads(0), 1);
  EXPECT_EQ(amcr::resolveThreads(3), 3);
}
}  // namespace
