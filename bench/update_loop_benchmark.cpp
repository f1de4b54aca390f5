// Speed of the relational update loop alone, one thread: the
// per-M-particle update of paper 3.6 (ObservationModel::measure, fast, and
// measureReference) and the heading proposal of seeding (bestHeadingBin, fast,
// and bestHeadingBinReference). The paper's comparison counts: 30 V-particles
// x 60 M-particles per prototype x 17 prototypes. Counters are rates:
// updates/s (relational-particle updates), calls/s.
//
//   rosrun amcr amcr_benchmark --benchmark_filter='UpdateLoop|BestHeadingBin'
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "amcr/filter/heading_proposal.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/filter/relational_update.h"
#include "bench_scenes.h"
#include "scene_drawing.h"

namespace
{
constexpr int kVParticles = 30;
constexpr int kMPerPrototype = 60;
constexpr int kPrototypes = 17;
constexpr int kClusters = 4;  // M-particle clouds per prototype, as after resampling

/// The M-particles of one V-particle: kMPerPrototype per prototype, in
/// kClusters clouds of +-3 px and +-0.2 rad around interior pixels.
amcr::MParticleSet benchMParticles(const amcr::PrototypeMemory& memory, std::mt19937_64& gen)
{
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  amcr::MParticleSet m;
  m.resize(memory.size() * kMPerPrototype);
  std::size_t i = 0;
  for (std::size_t p = 0; p < memory.size(); ++p)
  {
    const amcr::Prototype& prototype = memory[p];
    for (int c = 0; c < kClusters; ++c)
    {
      const cv::Point centre = prototype.interior()[gen() % prototype.interior().size()];
      const float heading = 2.f * static_cast<float>(M_PI) * unit(gen);
      for (int k = 0; k < kMPerPrototype / kClusters; ++k, ++i)
      {
        m.prototype[i] = static_cast<int>(p);
        m.x[i] = std::min(std::max(centre.x + 6.f * unit(gen) - 3.f, 0.f), prototype.width() - 1.f);
        m.y[i] = std::min(std::max(centre.y + 6.f * unit(gen) - 3.f, 0.f), prototype.height() - 1.f);
        m.theta[i] = heading + 0.4f * unit(gen) - 0.2f;
        m.shape[0][i] = m.shape[2][i] = 1.f;  // a frontal view shape (ray_correspondence affine)
      }
    }
  }
  return m;
}

/// A V-particle on the object: the rays the table holds at an M-particle's
/// pose, 1.5 times longer, with noise; one ray in ten invalid.
amcr::VRayEnds benchVEnds(const amcr::PrototypeMemory& memory, const amcr::MParticleSet& m, std::mt19937_64& gen)
{
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const std::size_t i = gen() % m.size();
  const amcr::Prototype& prototype = memory[m.prototype[i]];
  const cv::Point at = amcr::nearestTablePixel(m.x[i], m.y[i]);
  const int bin = amcr::angleToBin(m.theta[i]);
  amcr::VParticle v;
  v.x = 320.f;
  v.y = 240.f;
  v.theta = 2.f * static_cast<float>(M_PI) * unit(gen);
  float distance[amcr::kFeatureRays + 2];
  bool valid[amcr::kFeatureRays + 2];
  for (int j = 0; j < amcr::kFeatureRays + 2; ++j)
  {
    const int ray = j < amcr::kFeatureRays ? j * amcr::kFeatureBinStep
                                           : (j - amcr::kFeatureRays + 1) * amcr::kTriangleBinStep;
    const float d = prototype.distance(at.x, at.y, (bin + ray) % amcr::kDirectionBins);
    distance[j] = d > 0.f ? 1.5f * d + 4.f * unit(gen) - 2.f : 50.f * unit(gen) + 1.f;
    valid[j] = unit(gen) > 0.1f;
  }
  valid[0] = valid[amcr::kFeatureRays] = valid[amcr::kFeatureRays + 1] = true;  // a triangle to fit
  return amcr::rayEnds(v, distance, valid);
}

// One iteration: every V-particle's update of its 1020 M-particles. Args:
// path (0 measureReference, 1 measure), deviation space (0 image, 1
// prototype), ray correspondence (0 paper: per-bin lookups; 1 affine, the
// default: lookups along the view shape, then along A, no refits).
void BM_UpdateLoop(benchmark::State& state)
{
  const auto memory = amcr_bench::cachedMemory(kPrototypes);
  amcr::Params params;
  params.deviation_space = state.range(1) == 0 ? amcr::DeviationSpace::kImage : amcr::DeviationSpace::kPrototype;
  params.ray_correspondence = state.range(2) == 0 ? amcr::RayCorrespondence::kPaper : amcr::RayCorrespondence::kAffine;
  const amcr::ObservationModel model(params);
  std::mt19937_64 gen(16);
  std::vector<amcr::MParticleSet> m;
  std::vector<amcr::VRayEnds> v;
  for (int k = 0; k < kVParticles; ++k)
  {
    m.push_back(benchMParticles(*memory, gen));
    v.push_back(benchVEnds(*memory, m.back(), gen));
  }
  const bool fast = state.range(0) == 1;
  for (auto _ : state)
    for (int k = 0; k < kVParticles; ++k)
    {
      if (fast)
        model.measure(*memory, v[k], m[k], 0, m[k].size());
      else
        model.measureReference(*memory, v[k], m[k], 0, m[k].size());
      benchmark::DoNotOptimize(m[k].log_likelihood.data());
    }
  const double updates = static_cast<double>(kVParticles) * m[0].size();
  state.counters["updates"] = benchmark::Counter(state.iterations() * updates, benchmark::Counter::kIsRate);
  state.SetLabel(std::string(fast ? "measure" : "measureReference") + ", " +
                 amcr::toString(params.deviation_space) + " space, " + amcr::toString(params.ray_correspondence) +
                 " correspondence");
}
BENCHMARK(BM_UpdateLoop)
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({0, 0, 1})
    ->Args({1, 0, 1})
    ->Args({0, 1, 1})
    ->Args({1, 1, 1})
    ->Unit(benchmark::kMillisecond);

// bestHeadingBin at interior pixels for signatures of the table, scaled, with
// noise and a dropped ray now and then. Arg: 0 bestHeadingBinReference, 1 bestHeadingBin.
void BM_BestHeadingBin(benchmark::State& state)
{
  const auto memory = amcr_bench::cachedMemory(kPrototypes);
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  struct Call
  {
    const amcr::Prototype* prototype;
    cv::Point at;
    amcr::RaySignature signature;
  };
  std::vector<Call> calls;
  for (int c = 0; c < 1024; ++c)
  {
    const amcr::Prototype& p = (*memory)[gen() % memory->size()];
    const cv::Point at = p.interior()[gen() % p.interior().size()];
    amcr::RaySignature s =
        amcr_test::tableRays(p, at.x, at.y, static_cast<int>(gen() % amcr::kDirectionBins), 0.5f + 2.f * unit(gen));
    for (float& d : s.distance)
      d = gen() % 10 == 0 ? 0.f : (d > 0.f ? std::max(0.1f, d + 2.f * unit(gen) - 1.f) : d);
    calls.push_back({&p, at, s});
  }
  const bool fast = state.range(0) == 1;
  for (auto _ : state)
    for (const Call& c : calls)
      benchmark::DoNotOptimize(fast ? amcr::bestHeadingBin(*c.prototype, c.at.x, c.at.y, c.signature)
                                    : amcr::bestHeadingBinReference(*c.prototype, c.at.x, c.at.y, c.signature));
  state.counters["calls"] = benchmark::Counter(state.iterations() * static_cast<double>(calls.size()),
                                               benchmark::Counter::kIsRate);
  state.SetLabel(fast ? "bestHeadingBin" : "bestHeadingBinReference");
}
BENCHMARK(BM_BestHeadingBin)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
}  // namespace
