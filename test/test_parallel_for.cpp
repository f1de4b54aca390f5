// parallelFor (parallel_for.h): every index once, whatever the thread
// count, and an exception of the lowest failing index passed on; within a
// SingleThreadScope, all on the caller's thread. Its threads are its own:
// an OpenCV loop running on another thread, or a call made at the same time,
// does not take them. No speed is asserted: threads that must run at once
// meet, each waiting for the others up to kPatience.
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>

#include "amcr/base/parallel_for.h"

namespace
{
// Far longer than any thread waits to be scheduled on a loaded machine: a
// meeting that fails waits this long once, a meeting that succeeds does not.
constexpr std::chrono::seconds kPatience{20};

/// Threads that must run at once: each arrives and waits for the others.
class Meeting
{
public:
  explicit Meeting(int parties) : parties_(parties) {}

  /// True when every party arrived within kPatience of this one.
  bool attend()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    ++arrived_;
    all_there_.notify_all();
    return all_there_.wait_for(lock, kPatience, [&] { return arrived_ >= parties_; });
  }

private:
  const int parties_;
  int arrived_ = 0;
  std::mutex mutex_;
  std::condition_variable all_there_;
};

/// Closed until opened; wait() blocks until then.
class Gate
{
public:
  void open()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    opened_.notify_all();
  }
  void wait()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    opened_.wait(lock, [&] { return open_; });
  }

private:
  bool open_ = false;
  std::mutex mutex_;
  std::condition_variable opened_;
};

/// Ends the test program, saying why, when a test is not over in two
/// minutes: a deadlock fails the test instead of hanging it.
class Watchdog
{
public:
  explicit Watchdog(std::string test) : test_(std::move(test)), thread_([this] { watch(); }) {}
  ~Watchdog()
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      over_ = true;
    }
    over_changed_.notify_all();
    thread_.join();
  }

private:
  void watch()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!over_changed_.wait_for(lock, std::chrono::minutes(2), [&] { return over_; }))
    {
      std::fprintf(stderr, "%s: not over after 2 minutes (a deadlock?)\n", test_.c_str());
      std::abort();
    }
  }

  const std::string test_;
  bool over_ = false;
  std::mutex mutex_;
  std::condition_variable over_changed_;
  std::thread thread_;
};

/// The niceness of the calling thread (Linux: a thread's own).
int niceness()
{
  return getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
}

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

// Another thread inside an OpenCV loop (a memory rebuilt beside the stream
// runs OpenCV's resize, threshold and morphology loops): the recognizer's
// loops still run on the threads they ask for. With OpenCV's parallel_for_
// they ran on their caller alone (one parallel loop per process).
TEST(ParallelFor, RunsOnItsThreadsWhileAnotherThreadIsInsideAnOpenCVLoop)
{
  const Watchdog watchdog("RunsOnItsThreadsWhileAnotherThreadIsInsideAnOpenCVLoop");
  Gate release;
  std::atomic<int> inside{0};
  std::thread other([&] {
    cv::parallel_for_(
        cv::Range(0, 2),
        [&](const cv::Range&) {
          ++inside;
          release.wait();
        },
        2);
  });
  while (inside.load() == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));

  Meeting both(2);
  std::atomic<int> met{0};
  std::mutex mutex;
  std::set<std::thread::id> used;
  amcr::parallelFor(2, 2, [&](int) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      used.insert(std::this_thread::get_id());
    }
    if (both.attend())
      ++met;
  });
  release.open();
  other.join();
  EXPECT_EQ(met.load(), 2) << "the two pieces never ran at once";
  EXPECT_EQ(used.size(), 2u);
}

// Two threads calling at once (two recognizers in one process) each get
// their threads: the four pieces of the two calls run at the same time.
TEST(ParallelFor, CallsFromTwoThreadsAtOnceBothRunOnTheirThreads)
{
  const Watchdog watchdog("CallsFromTwoThreadsAtOnceBothRunOnTheirThreads");
  Meeting all(4);
  std::atomic<int> met{0};
  const auto call = [&] { amcr::parallelFor(2, 2, [&](int) { met += all.attend() ? 1 : 0; }); };
  std::thread first(call);
  std::thread second(call);
  first.join();
  second.join();
  EXPECT_EQ(met.load(), 4) << "the calls did not run side by side on two threads each";
}

// A call from a body of a call spread over threads runs on that body's
// thread: no deadlock, every index once, and no more threads than the
// outer call asked for. A call from a body of a call that runs on its
// caller alone is spread as any other.
TEST(ParallelFor, ACallFromABodyRunsOnThatBodysThread)
{
  const Watchdog watchdog("ACallFromABodyRunsOnThatBodysThread");
  constexpr int kOuter = 12;
  constexpr int kInner = 20;
  std::vector<std::atomic<int>> runs(kOuter * kInner);
  std::atomic<int> elsewhere{0};
  std::mutex mutex;
  std::set<std::thread::id> used;
  amcr::parallelFor(kOuter, 3, [&](int i) {
    const std::thread::id body_thread = std::this_thread::get_id();
    amcr::parallelFor(kInner, 4, [&](int j) {
      ++runs[i * kInner + j];
      if (std::this_thread::get_id() != body_thread)
        ++elsewhere;
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    });
    std::lock_guard<std::mutex> lock(mutex);
    used.insert(body_thread);
  });
  for (int k = 0; k < kOuter * kInner; ++k)
    EXPECT_EQ(runs[k].load(), 1) << "outer index " << k / kInner << ", inner " << k % kInner;
  EXPECT_EQ(elsewhere.load(), 0);
  EXPECT_LE(used.size(), 3u);

  Meeting both(2);
  std::atomic<int> met{0};
  amcr::parallelFor(1, 4, [&](int) { amcr::parallelFor(2, 2, [&](int) { met += both.attend() ? 1 : 0; }); });
  EXPECT_EQ(met.load(), 2) << "the inner call of an outer call on one thread was not spread";
}

TEST(ParallelFor, NeverRunsOnMoreThreadsThanAsked)
{
  for (int threads : {2, 3})
  {
    std::atomic<int> running{0};
    std::atomic<int> most{0};
    std::mutex mutex;
    std::set<std::thread::id> used;
    amcr::parallelFor(48, threads, [&](int) {
      const int now = ++running;
      int seen = most.load();
      while (now > seen && !most.compare_exchange_weak(seen, now))
      {
      }
      std::this_thread::sleep_for(std::chrono::microseconds(300));
      --running;
      std::lock_guard<std::mutex> lock(mutex);
      used.insert(std::this_thread::get_id());
    });
    EXPECT_LE(most.load(), threads);
    EXPECT_LE(used.size(), static_cast<std::size_t>(threads));
  }
}

// Exceptions of calls made at once, and of calls made from a body, each
// reach their own caller, the lowest failing index's; the calls after them
// run as before.
TEST(ParallelFor, EachCallerGetsTheExceptionOfItsOwnLowestIndex)
{
  const Watchdog watchdog("EachCallerGetsTheExceptionOfItsOwnLowestIndex");
  const auto failing = [](int first, int second) {
    std::string caught = "nothing";
    std::vector<std::atomic<int>> runs(60);
    try
    {
      amcr::parallelFor(60, 3, [&](int i) {
        ++runs[i];
        std::this_thread::sleep_for(std::chrono::microseconds(200));  // every thread takes some indices
        if (i == first || i == second)
          throw std::runtime_error(std::to_string(i));
      });
    }
    catch (const std::runtime_error& e)
    {
      caught = e.what();
    }
    for (int i = 0; i < 60; ++i)
      if (runs[i].load() != 1)
        return "index " + std::to_string(i) + " ran " + std::to_string(runs[i].load()) + " times";
    return caught;
  };
  std::string first;
  std::string second;
  std::thread a([&] { first = failing(41, 17); });
  std::thread b([&] { second = failing(55, 23); });
  a.join();
  b.join();
  EXPECT_EQ(first, "17");
  EXPECT_EQ(second, "23");

  // Thrown by an inner call, it leaves the outer body and is the outer call's.
  std::string caught = "nothing";
  try
  {
    amcr::parallelFor(8, 2, [&](int i) {
      amcr::parallelFor(8, 2, [&](int j) {
        if (j == 5 && (i == 3 || i == 6))
          throw std::runtime_error("inner " + std::to_string(i));
      });
    });
  }
  catch (const std::runtime_error& e)
  {
    caught = e.what();
  }
  EXPECT_EQ(caught, "inner 3");
  EXPECT_EQ(failing(0, 59), "0") << "a call after the exceptions";
}

// Each index writes only its own data, so the output does not depend on
// the thread count or on which thread ran what (pieces of uneven length).
TEST(ParallelFor, TheOutputIsTheSameOnAnyThreadCount)
{
  const auto run = [](int threads) {
    std::vector<std::uint64_t> out(300);
    amcr::parallelFor(static_cast<int>(out.size()), threads, [&](int i) {
      std::mt19937_64 rng(static_cast<std::uint64_t>(i));
      std::uint64_t sum = 0;
      for (int k = 0; k < 50 + (i * 7919) % 2000; ++k)
        sum ^= rng() + static_cast<std::uint64_t>(k);
      out[static_cast<std::size_t>(i)] = sum;
    });
    return out;
  };
  const std::vector<std::uint64_t> one = run(1);
  for (int threads : {2, 3, 5, 16})
    EXPECT_EQ(run(threads), one) << threads << " threads";
}

// The workers keep the priority of the thread that started them: a thread at
// niceness 10 (the nodelet's rebuilds) never starts one, and the pieces a
// call from it hands to workers run at the starter's priority.
TEST(ParallelFor, WorkersKeepThePriorityOfTheThreadThatStartedThem)
{
  const Watchdog watchdog("WorkersKeepThePriorityOfTheThreadThatStartedThem");
  const int threads = amcr::resolveThreads(0);
  if (threads < 2)
    GTEST_SKIP() << "one thread: nothing is handed to a worker";
  const int normal = niceness();
  if (normal > 9)
    GTEST_SKIP() << "this test already runs at niceness " << normal;
  amcr::startWorkerThreads();

  std::vector<int> seen(static_cast<std::size_t>(threads), -100);
  std::vector<std::thread::id> ran_on(static_cast<std::size_t>(threads));
  std::thread::id low_thread;
  bool lowered = false;
  std::atomic<int> met{0};
  std::thread low([&] {
    low_thread = std::this_thread::get_id();
    lowered = setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), normal + 10) == 0;
    Meeting all(threads);
    amcr::parallelFor(threads, threads, [&](int i) {
      seen[static_cast<std::size_t>(i)] = niceness();
      ran_on[static_cast<std::size_t>(i)] = std::this_thread::get_id();
      met += all.attend() ? 1 : 0;
    });
  });
  low.join();
  ASSERT_TRUE(lowered) << "cannot raise a thread's niceness here";
  EXPECT_EQ(met.load(), threads);
  int on_workers = 0;
  for (int i = 0; i < threads; ++i)
    if (ran_on[static_cast<std::size_t>(i)] != low_thread)
    {
      ++on_workers;
      EXPECT_EQ(seen[static_cast<std::size_t>(i)], normal) << "piece " << i << " ran on a worker of lower priority";
    }
  EXPECT_EQ(on_workers, threads - 1);
}
}  // namespace
