#include "amcr/base/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

#include <opencv2/core/utility.hpp>

namespace amcr
{
namespace
{
thread_local int single_thread_scopes = 0;  // SingleThreadScopes alive on this thread
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
  // A piece per thread that lasts long enough for every worker to be asked for.
  const int threads = resolveThreads(0);
  cv::parallel_for_(
      cv::Range(0, threads), [](const cv::Range&) { std::this_thread::sleep_for(std::chrono::milliseconds(2)); },
      threads);
}

void parallelFor(int count, int threads, const std::function<void(int)>& body)
{
  if (count <= 0)
    return;
  std::atomic<int> next{0};
  std::mutex failure_mutex;
  int failed_index = count;
  std::exception_ptr failure;
  // A worker takes the next index not taken yet until none is left.
  const auto work = [&] {
    for (int i = next++; i < count; i = next++)
    {
      try
      {
        body(i);
      }
      catch (...)
      {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (i < failed_index)
        {
          failed_index = i;
          failure = std::current_exception();
        }
      }
    }
  };
  const int workers = single_thread_scopes > 0 ? 1 : std::min(count, std::max(1, threads));
  if (workers == 1)
    work();
  else
    // One stripe per worker: OpenCV never runs more stripes at once than
    // there are, which bounds the threads of this call.
    cv::parallel_for_(
        cv::Range(0, workers),
        [&](const cv::Range& stripes) {
          for (int s = stripes.start; s < stripes.end; ++s)
            work();
        },
        workers);
  if (failure)
    std::rethrow_exception(failure);
}
}  // namespace amcr
