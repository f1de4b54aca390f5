// Work spread over threads with a deterministic result: each index is one
// independent piece of work that writes only its own data, so the output is
// the same for any thread count (issue 16). OpenCV's parallel_for_ runs the
// workers (its backend: TBB or a thread pool); the thread count is bounded
// per call, never by changing OpenCV's process-wide setting.
#pragma once

#include <functional>

namespace amcr
{
/// The threads a `num_threads` parameter asks for: 0 = as many as OpenCV
/// may use (cv::getNumThreads(): every core unless the process said
/// otherwise), else num_threads itself.
int resolveThreads(int num_threads);

/// Runs body(i) for every i in [0, count) on at most `threads` threads, each
/// taking the next index not taken yet (so uneven pieces balance). When a
/// body throws, the others still run and the exception of the lowest index
/// is rethrown at the end. threads <= 1 runs in index order on the caller's
/// thread.
void parallelFor(int count, int threads, const std::function<void(int)>& body);
}  // namespace amcr
