#include "amcr/base/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include <opencv2/core/utility.hpp>

namespace amcr
{
namespace
{
thread_local int single_thread_scopes = 0;  // SingleThreadScopes alive on this thread
thread_local int spread_bodies = 0;         // bodies of calls spread over threads running on this thread

/// One call of parallelFor: the indices it hands out and the exception of
/// its lowest failing index.
class Loop
{
public:
  Loop(int count, const std::function<void(int)>& body, bool spread) : count_(count), body_(body), spread_(spread)
  {
  }

  /// Runs the next index not taken yet until none is left.
  void work()
  {
    if (spread_)
      ++spread_bodies;
    for (int i = next_++; i < count_; i = next_++)
    {
      try
      {
        body_(i);
      }
      catch (...)
      {
        std::lock_guard<std::mutex> lock(failure_mutex_);
        if (i < failed_index_)
        {
          failed_index_ = i;
          failure_ = std::current_exception();
        }
      }
    }
    if (spread_)
      --spread_bodies;
  }

  /// Rethrows the exception of the lowest failing index, if one failed.
  void rethrow() const
  {
    if (failure_)
      std::rethrow_exception(failure_);
  }

  int helpers = 0;  // workers inside work(), counted under the pool's mutex

private:
  const int count_;
  const std::function<void(int)>& body_;
  const bool spread_;
  std::atomic<int> next_{0};
  std::mutex failure_mutex_;
  int failed_index_ = count_;
  std::exception_ptr failure_;
};

/// amcr's workers. A call asks for a number of helpers by queueing its loop
/// that many times; each idle worker takes one entry and works on that loop
/// until it has no index left. The caller works on its loop meanwhile, so it
/// finishes even if no worker ever comes; it then withdraws the entries no
/// worker took and waits for the workers still inside. The pool starts a
/// worker whenever more entries wait than workers are idle, so that calls
/// from several threads at once each get theirs.
class Workers
{
public:
  static Workers& instance()
  {
    static Workers workers;
    return workers;
  }

  ~Workers()
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& thread : threads_)
      if (thread.get_id() == std::this_thread::get_id())
        thread.detach();  // the process ends from a body on this worker: it cannot wait for itself
      else
        thread.join();
  }

  /// Starts workers until at least `count` are there.
  void reserve(int count)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    start(count - static_cast<int>(threads_.size()));
  }

  /// Runs `loop` on the calling thread and on up to `helpers` workers.
  void run(Loop& loop, int helpers)
  {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.insert(queue_.end(), helpers, &loop);
      start(static_cast<int>(queue_.size()) - idle_);
    }
    for (int h = 0; h < helpers; ++h)
      wake_.notify_one();
    loop.work();
    std::unique_lock<std::mutex> lock(mutex_);
    queue_.erase(std::remove(queue_.begin(), queue_.end(), &loop), queue_.end());
    done_.wait(lock, [&] { return loop.helpers == 0; });
  }

private:
  Workers() = default;

  /// Starts `count` workers (none when count <= 0); under mutex_. A worker
  /// the system refuses is done without: the caller does the work.
  void start(int count)
  {
    for (int k = 0; k < count; ++k)
    {
      try
      {
        threads_.emplace_back([this] { serve(); });
      }
      catch (const std::system_error&)
      {
        return;
      }
      ++idle_;
    }
  }

  void serve()
  {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;)
    {
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (queue_.empty())
        return;  // stopping
      Loop* loop = queue_.front();
      queue_.pop_front();
      --idle_;
      ++loop->helpers;
      lock.unlock();
      loop->work();
      lock.lock();
      ++idle_;
      if (--loop->helpers == 0)
        done_.notify_all();  // under the lock: the caller may destroy the loop as soon as it sees 0
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;  // an entry was queued, or the pool stops
  std::condition_variable done_;  // a loop's last worker left it
  std::deque<Loop*> queue_;       // one entry per helper a call still waits for
  std::vector<std::thread> threads_;
  int idle_ = 0;  // workers not inside a loop
  bool stopping_ = false;
};
}  // namespace

SingleThreadScope::SingleThreadScope() { ++single_thread_scopes; }

SingleThreadScope::~SingleThreadScope() { --single_thread_scopes; }

int resolveThreads(int num_threads)
{
  if (single_thread_scopes > 0)
    return 1;
  return num_threads > 0 ? num_threads : std::max(1, cv::getNumThreads());
}

void startWorkerThreads()
{
  const int threads = resolveThreads(0);
  Workers::instance().reserve(threads - 1);  // the caller of a loop is its first thread
  // OpenCV's own loops (within resize, filters, ...) run on OpenCV's workers: a piece per thread that
  // lasts long enough for every one of them to be asked for.
  cv::parallel_for_(
      cv::Range(0, threads), [](const cv::Range&) { std::this_thread::sleep_for(std::chrono::milliseconds(2)); },
      threads);
}

void parallelFor(int count, int threads, const std::function<void(int)>& body)
{
  if (count <= 0)
    return;
  const bool alone = single_thread_scopes > 0 || spread_bodies > 0;
  const int workers = alone ? 1 : std::min(count, std::max(1, threads));
  Loop loop(count, body, workers > 1);
  if (workers == 1)
    loop.work();
  else
    Workers::instance().run(loop, workers - 1);
  loop.rethrow();
}
}  // namespace amcr
