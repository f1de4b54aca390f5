// parallelFor (parallel_for.h): every index once, whatever the thread
// count, and an exception of the lowest failing index passed on; within a
// SingleThreadScope, all on the caller's thread.
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/parallel_for.h"

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

TEST(ParallelFor, ASingleThreadScopeKeepsTheWorkOnItsThread)
{
  const auto threadsUsed = [](int threads) {
    std::mutex mutex;
    std::set<std::thread::id> used;
    amcr::parallelFor(64, threads, [&](int) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));  // long enough for several workers to take part
      std::lock_guard<std::mutex> lock(mutex);
      used.insert(std::this_thread::get_id());
    });
    return used;
  };
  {
    const amcr::SingleThreadScope outer;
    {
      const amcr::SingleThreadScope inner;  // scopes nest
    }
    EXPECT_EQ(amcr::resolveThreads(0), 1);
    EXPECT_EQ(amcr::resolveThreads(4), 1);
    EXPECT_EQ(threadsUsed(4), std::set<std::thread::id>{std::this_thread::get_id()});
  }
  EXPECT_EQ(amcr::resolveThreads(4), 4) << "the scope outlived itself";
  // On another thread the scope of this one does not count.
  const amcr::SingleThreadScope here;
  int elsewhere = 0;
  std::thread([&] { elsewhere = amcr::resolveThreads(4); }).join();
  EXPECT_EQ(elsewhere, 4);
}
}  // namespace
