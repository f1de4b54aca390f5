// Speed of the core (Google Benchmark): relational-particle updates per
// second as the particle counts and the memory grow, and the cost of a
// prototype's lookup table. Inputs are drawn in code (test/scene_drawing.h).
//
//   rosrun amcr amcr_benchmark [--benchmark_filter=Step]
//
// One core: OpenCV's own threads are switched off before anything runs
// (BM_MemoryBuild sets the count it is given, and restores it).
// scripts/benchmark runs it with --benchmark_format=json for the report's speed section.
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "amcr/memory/table_cache.h"
#include "bench_scenes.h"
#include "scene_drawing.h"

namespace
{
using amcr_bench::cachedMemory;
using amcr_test::ShapeId;

const std::vector<cv::Mat>& frames() { return amcr_bench::staticFrames(); }

// One iteration (paper 3.6) on a 640x480 frame with the paper's counts
// (m_particles_per_v 0, no proposal index, no KLD-sampling): args
// V-particles, M-particles per prototype per V, prototypes. items/s =
// relational-particle updates per second.
void BM_RecognizerStep(benchmark::State& state)
{
  amcr::Params params;
  params.num_v_particles = static_cast<int>(state.range(0));
  params.m_particles_per_prototype = static_cast<int>(state.range(1));
  params.m_particles_per_v = 0;
  params.index_share = 0.0;
  params.kld_error = 0.0;
  const int prototypes = static_cast<int>(state.range(2));
  amcr::Recognizer recognizer(params, cachedMemory(prototypes));
  std::size_t k = 0;
  for (int warm = 0; warm < 20; ++warm)  // past the first iterations, as in a running stream
    recognizer.step(frames()[k++ % frames().size()]);
  for (auto _ : state)
    benchmark::DoNotOptimize(recognizer.step(frames()[k++ % frames().size()]));
  const double updates = static_cast<double>(params.num_v_particles) * params.m_particles_per_prototype * prototypes;
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * updates));
  state.counters["relational_particles"] = updates;
}
BENCHMARK(BM_RecognizerStep)
    ->Args({30, 60, 3})   // the paper's video experiment
    ->Args({60, 60, 3})   // the defaults
    ->Args({10, 50, 3})   // the paper's figure 2
    ->Args({30, 60, 17})  // the paper's comparison memory
    ->Args({120, 60, 3})
    // Scaling series: V count (60 M, 3 prototypes), M per prototype (30 V, 3 prototypes),
    // prototype count (30 V x 60 M).
    ->Args({15, 60, 3})
    ->Args({240, 60, 3})
    ->Args({30, 15, 3})
    ->Args({30, 30, 3})
    ->Args({30, 120, 3})
    ->Args({30, 240, 3})
    ->Args({30, 60, 1})
    ->Args({30, 60, 8})
    ->Args({30, 60, 35})
    ->Args({30, 60, 70})
    ->Unit(benchmark::kMillisecond);

// One iteration with the defaults (a budget of M-particles per V-particle,
// the proposal index, KLD-sampling: the time no longer grows with the
// memory as with the paper's count per prototype): args V-particles,
// prototypes. items/s = relational-particle updates per second, at the mean
// count KLD-sampling left.
void BM_BudgetStep(benchmark::State& state)
{
  amcr::Params params;
  params.num_v_particles = static_cast<int>(state.range(0));
  amcr::Recognizer recognizer(params, cachedMemory(static_cast<int>(state.range(1))));
  std::size_t k = 0;
  for (int warm = 0; warm < 20; ++warm)
    recognizer.step(frames()[k++ % frames().size()]);
  double m_sum = 0.0;
  for (auto _ : state)
  {
    const amcr::RecognitionResult result = recognizer.step(frames()[k++ % frames().size()]);
    m_sum += result.mean_m_particles;
    benchmark::DoNotOptimize(result);
  }
  const double mean_m = state.iterations() > 0 ? m_sum / state.iterations() : 0.0;
  state.SetItemsProcessed(static_cast<int64_t>(m_sum * params.num_v_particles));
  state.counters["mean_m_per_v"] = mean_m;
}
BENCHMARK(BM_BudgetStep)
    ->Args({60, 3})
    ->Args({60, 17})
    ->Args({60, 35})
    ->Args({60, 70})
    ->Args({30, 17})
    ->Unit(benchmark::kMillisecond);

// Building the proposal index over a memory (args: prototypes).
void BM_ProposalIndex(benchmark::State& state)
{
  const std::shared_ptr<const amcr::PrototypeMemory> memory = cachedMemory(static_cast<int>(state.range(0)));
  const amcr::Params defaults;
  std::size_t entries = 0;
  for (auto _ : state)
  {
    const amcr::ProposalIndex index(*memory, defaults.index_stride);
    entries = index.size();
    benchmark::DoNotOptimize(entries);
  }
  state.counters["entries"] = static_cast<double>(entries);
}
BENCHMARK(BM_ProposalIndex)->Arg(17)->Arg(70)->Unit(benchmark::kMillisecond);

// Building one prototype's lookup table (args: prototype_size px).
void BM_PrototypeTable(benchmark::State& state)
{
  const cv::Mat image = amcr_test::drawPrototype(ShapeId::kStar);
  std::size_t bytes = 0;
  for (auto _ : state)
  {
    const amcr::Prototype prototype("star", image, static_cast<int>(state.range(0)), 40.0, 1.0);
    bytes = prototype.tableBytes();
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["table_MB"] = bytes / 1e6;
}
BENCHMARK(BM_PrototypeTable)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

/// A directory of `count` drawn prototype images (as memoryOf), written once.
const amcr_test::TempDir& imageDirectory(int count)
{
  static std::vector<std::unique_ptr<amcr_test::TempDir>> directories(128);
  if (!directories[count])
  {
    directories[count] = std::make_unique<amcr_test::TempDir>();
    const std::vector<ShapeId>& shapes = amcr_test::allShapes();
    for (int i = 0; i < count; ++i)
    {
      const ShapeId id = shapes[i % shapes.size()];
      cv::imwrite(directories[count]->file(amcr_test::shapeName(id) + "_" + std::to_string(i) + ".png"),
                  amcr_test::drawPrototype(id));
    }
  }
  return *directories[count];
}

// A whole memory as the nodelet loads it: the tables of a
// directory of images, then the proposal index (its k-d tree in the same
// cache). Args: prototypes, OpenCV
// threads, cache (0: none, 1: cold, emptied before each run, so the files
// are written, 2: warm, every table read from it).
void BM_MemoryBuild(benchmark::State& state)
{
  const int count = static_cast<int>(state.range(0)), cache = static_cast<int>(state.range(2));
  const amcr_test::TempDir& images = imageDirectory(count);
  const amcr_test::TempDir cache_dir;
  amcr::Params params;
  params.table_cache_dir = cache == 0 ? "none" : cache_dir.file("tables");
  const int threads = cv::getNumThreads();
  cv::setNumThreads(static_cast<int>(state.range(1)));
  const amcr::TableCache tree_cache(amcr::tableCacheDirectory(params.table_cache_dir));
  const amcr::TableCache* index_cache = tree_cache.readable() ? &tree_cache : nullptr;
  if (cache == 2)
  {
    const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(images.path(), params);
    const amcr::ProposalIndex index(memory, params.index_stride, {}, {}, index_cache);
  }
  std::size_t read = 0;
  double tables_ms = 0.0, index_ms = 0.0;
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  for (auto _ : state)
  {
    if (cache == 1)
    {
      state.PauseTiming();
      std::filesystem::remove_all(cache_dir.file("tables"));
      state.ResumeTiming();
    }
    const Clock::time_point start = Clock::now();
    const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(images.path(), params);
    const Clock::time_point loaded = Clock::now();
    const amcr::ProposalIndex index(memory, params.index_stride, {}, {}, index_cache);
    tables_ms += ms(loaded - start);
    index_ms += ms(Clock::now() - loaded);
    read = memory.cacheCounts().read;
    benchmark::DoNotOptimize(index.size());
  }
  cv::setNumThreads(threads);
  // The two parts: the tables, then the index (its entries computed, its
  // k-d tree read from the cache or built and stored, as the recognizer does).
  state.counters["from_cache"] = static_cast<double>(read);
  state.counters["tables_ms"] = state.iterations() ? tables_ms / state.iterations() : 0.0;
  state.counters["index_ms"] = state.iterations() ? index_ms / state.iterations() : 0.0;
}
BENCHMARK(BM_MemoryBuild)
    ->Args({70, 1, 0})
    ->Args({70, 2, 0})
    ->Args({70, 2, 1})
    ->Args({70, 2, 2})
    ->Args({70, 1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
}  // namespace

int main(int argc, char** argv)
{
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
