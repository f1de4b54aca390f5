// A whole frame: 640x480, the default counts (60 V-particles,
// KLD-sampling of up to 1000 M-particles each, the proposal index), the
// optical flow on, a memory of drawn prototypes, an arrow moving over
// clutter. Args: prototypes, threads (0 = every core). The counters split
// the time of a frame by phase (RecognitionResult::times), ms; items/s =
// relational-particle updates per second over the whole frame.
#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>

#include "amcr/recognizer.h"
#include "bench_scenes.h"

namespace
{
void BM_Frame(benchmark::State& state)
{
  amcr::Params params;
  params.num_threads = static_cast<int>(state.range(1));
  // OpenCV's own work (blur, pyramid, flow) gets the same threads.
  const int opencv_threads = cv::getNumThreads();
  cv::setNumThreads(params.num_threads == 0 ? -1 : params.num_threads);
  amcr::Recognizer recognizer(params, amcr_bench::cachedMemory(static_cast<int>(state.range(0))));
  const std::vector<cv::Mat>& sequence = amcr_bench::movingFrames();
  std::size_t k = 0;
  for (int warm = 0; warm < 20; ++warm)  // past the first iterations, as in a running stream
    recognizer.step(sequence[k++ % sequence.size()]);
  amcr::StepTimes sum;
  double updates = 0.0;
  for (auto _ : state)
  {
    const amcr::RecognitionResult result = recognizer.step(sequence[k++ % sequence.size()]);
    sum.prepare_ms += result.times.prepare_ms;
    sum.flow_ms += result.times.flow_ms;
    sum.updates_ms += result.times.updates_ms;
    sum.extraction_ms += result.times.extraction_ms;
    updates += result.mean_m_particles * params.num_v_particles * result.iterations;
  }
  const double frames = static_cast<double>(state.iterations());
  state.counters["prepare_ms"] = sum.prepare_ms / frames;
  state.counters["flow_ms"] = sum.flow_ms / frames;
  state.counters["updates_ms"] = sum.updates_ms / frames;
  state.counters["extraction_ms"] = sum.extraction_ms / frames;
  state.counters["updates_per_s_in_updates"] = sum.updates_ms > 0 ? 1000.0 * updates / sum.updates_ms : 0.0;
  state.SetItemsProcessed(static_cast<int64_t>(updates));
  cv::setNumThreads(opencv_threads);
}
BENCHMARK(BM_Frame)
    ->Args({17, 1})
    ->Args({17, 2})
    ->Args({17, 0})
    ->Args({3, 1})
    ->Args({70, 1})
    ->Args({70, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
}  // namespace
