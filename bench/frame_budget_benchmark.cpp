// Time per frame under a frame budget (the recognizer keeps up with the camera
// by splitting iterations over frames): a 640x480 sequence with a
// moving arrow over clutter, the paper's counts (30 V x 60 M per prototype,
// 3 prototypes) and the flow on. Each benchmark iteration is one frame; the
// counters give the slowest frame, the share of frames over the budget and
// the iterations (paper 3.6) run per frame. Arg: budget in ms, 0 = none.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "amcr/recognizer.h"
#include "bench_scenes.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

void BM_FrameBudget(benchmark::State& state)
{
  static const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar});
  amcr::Params params;
  params.num_v_particles = 30;
  params.frame_budget_ms = static_cast<double>(state.range(0));
  amcr::Recognizer recognizer(params, memory);
  const std::vector<cv::Mat>& sequence = amcr_bench::movingFrames();  // rendered before the clock runs
  std::size_t k = 0;
  double slowest = 0.0, iterations = 0.0;
  long frames = 0, over = 0;
  for (auto _ : state)
  {
    const auto start = std::chrono::steady_clock::now();
    const amcr::RecognitionResult result = recognizer.step(sequence[k++ % sequence.size()]);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    slowest = std::max(slowest, ms);
    over += params.frame_budget_ms > 0.0 && ms > params.frame_budget_ms;
    iterations += result.iterations;
    ++frames;
  }
  state.counters["slowest_ms"] = slowest;
  state.counters["over_budget_share"] = frames ? static_cast<double>(over) / frames : 0.0;
  state.counters["iterations_per_frame"] = frames ? iterations / frames : 0.0;
}
BENCHMARK(BM_FrameBudget)->Arg(0)->Arg(16)->Arg(8)->Iterations(200)->Unit(benchmark::kMillisecond);
}  // namespace
