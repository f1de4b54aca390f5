// Work spread over threads with a deterministic result: each index is one
// independent piece of work that writes only its own data, so the output is
// the same for any thread count. The thread count is bounded per call, never
// by changing a process-wide setting.
//
// The threads are amcr's own: a pool of workers that only parallelFor uses,
// plus the calling thread. OpenCV's parallel_for_ runs one parallel loop at a
// time in the whole process: a loop that starts while another runs, on any
// thread, runs serially on its caller's thread. A memory built beside a
// running recognizer runs OpenCV loops of its own (resize, threshold,
// morphology), so for as long as it lasted every loop of the recognizer ran
// on one thread. TBB (which Debian's OpenCV runs on) is no way out: its
// workers are one pool for the whole process, shared with OpenCV's loops and
// as many as the cores less one (a single worker on two cores), so while an
// OpenCV loop holds them a task_arena of amcr's own gets none; more of them
// takes a process-wide setting (tbb::global_control) that OpenCV and the
// host would inherit. With workers of its own, a recognizer's loops keep
// their threads whatever else the process runs.
#pragma once

#include <functional>

namespace amcr
{
/// The threads a `num_threads` parameter asks for: 0 = as many as OpenCV
/// may use (cv::getNumThreads(): every core unless the process said
/// otherwise, e.g. cv::setNumThreads(1)), else num_threads itself; 1 within
/// a SingleThreadScope.
int resolveThreads(int num_threads);

/// Runs body(i) for every i in [0, count) on at most `threads` threads (the
/// caller's and workers of amcr's pool), each taking the next index not taken
/// yet (so uneven pieces balance). When a body throws, the others still run
/// and the exception of the lowest index is rethrown at the end. threads <= 1,
/// or a SingleThreadScope on the caller's thread, runs in index order on the
/// caller's thread; so does a call made from a body of a call that runs on
/// several threads (the outer call's threads bound the work it spreads).
/// Calls from several threads at once each get workers of their own: the
/// pool starts more when all of its workers are busy.
void parallelFor(int count, int threads, const std::function<void(int)>& body);

/// Starts amcr's workers (enough for a call on resolveThreads(0) threads)
/// and OpenCV's now, from the calling thread: a thread inherits the CPU
/// priority of the thread that starts it, so a process that lowers the
/// priority of one of its threads starts them first. Later the pool starts a
/// worker only when a parallelFor finds them all busy, from that call's
/// thread; a call within a SingleThreadScope never does (it runs on its own
/// thread).
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
