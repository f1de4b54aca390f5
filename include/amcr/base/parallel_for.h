// Work spread over threads with a deterministic result: each index is one
// independent piece of work that writes only its own data, so the output is
// the same for any thread count. OpenCV's parallel_for_ runs the
// workers (its backend: TBB or a thread pool); the thread count is bounded
// per call, never by changing OpenCV's process-wide setting.
//
// OpenCV runs one parallel loop at a time in the whole process: a loop that
// starts while another runs is run serially on its caller's thread. Work done
// beside a running recognizer (a memory built while images are recognized)
// therefore keeps to its own thread (SingleThreadScope), or for as long as
// it lasts the recognizer's loops would each run on one thread.
#pragma once

#include <functional>

namespace amcr
{
/// The threads a `num_threads` parameter asks for: 0 = as many as OpenCV
/// may use (cv::getNumThreads(): every core unless the process said
/// otherwise), else num_threads itself; 1 within a SingleThreadScope.
int resolveThreads(int num_threads);

/// Runs body(i) for every i in [0, count) on at most `threads` threads, each
/// taking the next index not taken yet (so uneven pieces balance). When a
/// body throws, the others still run and the exception of the lowest index
/// is rethrown at the end. threads <= 1, or a SingleThreadScope on the
/// caller's thread, runs in index order on the caller's thread.
void parallelFor(int count, int threads, const std::function<void(int)>& body);

/// Starts OpenCV's worker threads now, from the calling thread: a thread
/// inherits the CPU priority of the thread that starts it, so a process
/// that lowers the priority of one of its threads starts them first.
void startWorkerThreads();

/// While one lives on a thread, the work that thread spreads through
/// parallelFor and resolveThreads runs on that thread alone.
class SingleThreadScope
{
public:
  SingleThreadScope();
  ~SingleThreadScope();
  SingleThreadScope(const SingleThreadScope&) = delete;
  SingleThreadScope& operator=(const SingleThreadScope&) = delete;
};
}  // namespace amcr
