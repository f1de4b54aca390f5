// Recognition with the paper's 17 prototypes in memory, where the paper's
// fixed count of M-particles per prototype makes the time grow with the memory;
// inputs
// drawn in code: the five drawn silhouettes and twelve random ones. The
// M-particles of a V-particle are a budget shared among the prototypes
// (m_particles_per_v), a share of the new ones proposed by the index, and
// KLD-sampling adapts their number. A drawn target over clutter must be
// reported with the right label and its corners within the tolerance; a
// clutter-only scene must report nothing; the counts stay in their bounds
// and fall once the particles agree.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/extraction/object_extractor.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

// Iterations to a correct report. Measured with recognizer seeds 1-3 over
// the three scenes below: arrow 8-19, crescent 5-24, flag 6-11 (the paper's
// count per prototype without the index: crescent 7-14, flag 11-24; an
// arrow over the clutter of seed 301 was found by neither).
constexpr int kMaxIterations = 60;
constexpr double kCornerTolerance = 6.0;  // px, mean corner error of prototype_to_image
constexpr int kRandomPrototypes = 12;

std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m = [] {
    auto built = std::make_shared<amcr::PrototypeMemory>();
    const amcr::Params params;
    for (ShapeId id : amcr_test::allShapes())
      built->add(amcr_test::shapeName(id), amcr_test::drawPrototype(id), params);
    for (int i = 0; i < kRandomPrototypes; ++i)
      built->add("random_" + std::to_string(i), amcr_test::drawRandomSilhouette(1000 + i), params);
    return built;
  }();
  return m;
}

amcr::Params params()
{
  amcr::Params p;  // defaults: the budget, the index and KLD-sampling on
  p.seed = 1;
  return p;
}

/// The end-to-end scenes' clutter (the defaults) without their silhouettes,
/// which are in this memory.
amcr_test::Clutter clutter(std::uint64_t seed)
{
  amcr_test::Clutter c;
  c.seed = seed;
  return c;
}

struct Target
{
  ShapeId shape;
  cv::Point2d centre;
  double rotation;  // rad
  double scale_x, scale_y, shear;
  std::uint64_t clutter_seed;
};

void PrintTo(const Target& t, std::ostream* os) { *os << amcr_test::shapeName(t.shape) << " " << t.clutter_seed; }

class LargeMemory : public ::testing::TestWithParam<Target>
{
};

/// The frame (1-based) from which recognizer `params` on `frames` of target `t` reports its label
/// within kCornerTolerance of the truth, -1 when none of them does; `other` receives the first
/// other report (label, iteration, place) when given.
int firstCorrect(const Target& t, const std::vector<cv::Mat>& frames, const amcr::Params& params, std::string* other)
{
  const amcr::Affine truth =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), t.centre, t.rotation, t.scale_x, t.scale_y, t.shear);
  const std::string label = amcr_test::shapeName(t.shape);
  amcr::Recognizer recognizer(params, memory());
  int first_correct = -1;
  for (std::size_t k = 0; k < frames.size() && first_correct < 0; ++k)
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      if (o.label == label && amcr_test::cornerError(o.prototype_to_image, truth) <= kCornerTolerance)
        first_correct = static_cast<int>(k) + 1;
      else if (other && other->empty())
      {
        const cv::Point2d at = amcr::applyAffine(o.prototype_to_image, amcr_test::prototypeCentre());
        *other = o.label + " at iteration " + std::to_string(k + 1) + " at (" + std::to_string(std::lround(at.x)) +
                 ", " + std::to_string(std::lround(at.y)) + ")";
      }
    }
  return first_correct;
}

/// `iterations` frames of target `t` over its clutter.
std::vector<cv::Mat> renderTarget(const Target& t, int iterations)
{
  amcr_test::Scene scene;
  scene.objects.push_back(
      {t.shape, amcr_test::makeAffine(amcr_test::prototypeCentre(), t.centre, t.rotation, t.scale_x, t.scale_y, t.shear)});
  scene.clutter = clutter(t.clutter_seed);
  return amcr_test::renderSequence(scene, iterations);
}

const std::vector<Target> kTargets = {{ShapeId::kArrow, {330, 250}, 35 * M_PI / 180, 0.85, 0.75, 0.25, 101},
                                      {ShapeId::kCrescent, {300, 230}, -50 * M_PI / 180, 0.9, 1.0, -0.2, 302},
                                      {ShapeId::kFlag, {320, 240}, 100 * M_PI / 180, 0.9, 0.85, 0.1, 303}};

TEST_P(LargeMemory, RecognizesTheTargetAmongSeventeenPrototypes)
{
  const Target t = GetParam();
  ASSERT_EQ(memory()->size(), 17u);
  const std::string label = amcr_test::shapeName(t.shape);
  std::string wrong;
  const int first_correct = firstCorrect(t, renderTarget(t, kMaxIterations), params(), &wrong);
  std::cout << "[ e2e      ] " << label << " " << t.clutter_seed << ": first correct at iteration " << first_correct
            << (wrong.empty() ? "" : "; other report: " + wrong) << std::endl;
  EXPECT_GT(first_correct, 0) << label << " not reported within " << kCornerTolerance << " px in " << kMaxIterations
                              << " iterations" << (wrong.empty() ? "" : "; other report: " + wrong);
}

INSTANTIATE_TEST_SUITE_P(SeventeenPrototypes, LargeMemory, ::testing::ValuesIn(kTargets),
                         [](const ::testing::TestParamInfo<Target>& info) {
                           return amcr_test::shapeName(info.param.shape) + "_" +
                                  std::to_string(info.param.clutter_seed);
                         });

// Recall, not a lottery: each scene with recognizer seeds 1-5 (1-3 under the
// sanitizers, test/run_length.h) must be right
// within kMaxIterations, and most of them within kQuickIterations (the aim
// is all of them; measured with the densest-mode cluster: 11 of 15, the
// others at iterations 16-47).
constexpr int kQuickIterations = 15;
constexpr int kMinQuick = 9;  // of 15: three fifths

TEST(LargeMemoryRecall, EverySeedFindsEveryTarget)
{
  const int seeds = amcr_test::runLength(5, 3);
  const int runs = seeds * static_cast<int>(kTargets.size());
  std::string summary;
  int misses = 0, quick = 0;
  for (const Target& t : kTargets)
  {
    const std::vector<cv::Mat> frames = renderTarget(t, kMaxIterations);
    summary += "\n  " + amcr_test::shapeName(t.shape) + ":";
    for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed)
    {
      amcr::Params p = params();
      p.seed = seed;
      const int first_correct = firstCorrect(t, frames, p, nullptr);
      summary += " " + (first_correct > 0 ? std::to_string(first_correct) : std::string("-"));
      misses += first_correct > 0 ? 0 : 1;
      quick += first_correct > 0 && first_correct <= kQuickIterations ? 1 : 0;
    }
  }
  std::cout << "[ recall   ] first correct iteration, recognizer seeds 1-" << seeds << ":" << summary << std::endl;
  EXPECT_EQ(misses, 0) << "not right within " << kMaxIterations << " iterations:" << summary;
  EXPECT_GE(15 * quick, kMinQuick * runs) << "right within " << kQuickIterations << " iterations in " << quick << " of "
                                           << runs << ":" << summary;
}

TEST(LargeMemoryClutter, NothingIsReported)
{
  amcr_test::Scene scene;
  scene.clutter = clutter(304);
  scene.clutter.random_shapes = 10;
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, kMaxIterations);
  amcr::Recognizer recognizer(params(), memory());
  int reports = 0;
  std::string first;
  for (int k = 0; k < kMaxIterations; ++k)
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      ++reports;
      if (first.empty())
        first = o.label + " at iteration " + std::to_string(k + 1);
    }
  EXPECT_EQ(reports, 0) << "false positives, first: " << first;
}

// KLD-sampling: every V-particle's count stays within [min, budget] on
// every iteration and starts at the budget; once V-particles converge on the
// target, the converged ones hold fewer M-particles than the others, and
// the fewest held falls well below the budget.
TEST(KldSampling, TheCountFallsAsTheParticlesConvergeAndStaysInItsBounds)
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250},
                                                                   0.6, 0.85, 0.75, 0.25)});
  scene.clutter = clutter(301);
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, 40);
  const amcr::Params p = params();
  amcr::Recognizer recognizer(p, memory());
  double converged_sum = 0.0, spread_sum = 0.0;
  int converged_n = 0, spread_n = 0;
  std::size_t fewest = static_cast<std::size_t>(p.m_particles_per_v);
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    const amcr::RecognitionResult result = recognizer.step(frames[k]);
    const amcr::ParticleFilter& filter = recognizer.filter();
    const std::vector<amcr::VParticleCluster> clusters = amcr::filterClusters(filter);
    for (std::size_t v = 0; v < filter.vParticles().size(); ++v)
    {
      const std::size_t count = filter.mRange(static_cast<int>(v)).size();
      ASSERT_GE(count, static_cast<std::size_t>(p.min_m_particles_per_v)) << "V-particle " << v;
      ASSERT_LE(count, static_cast<std::size_t>(p.m_particles_per_v)) << "V-particle " << v;
      if (k == 0)
        continue;
      fewest = std::min(fewest, count);
      if (clusters[v].converged)
      {
        converged_sum += count;
        ++converged_n;
      }
      else
      {
        spread_sum += count;
        ++spread_n;
      }
    }
    EXPECT_DOUBLE_EQ(result.mean_m_particles, filter.meanMParticles());
    if (k == 0)
    {
      // The first update of fresh V-particles: their particles spread over so many bins that
      // KLD-sampling keeps about the budget; one whose first scan the index matched closely may
      // concentrate at once (its proposals weigh by their likelihood: proposal_correction 0).
      EXPECT_GE(result.mean_m_particles, 0.95 * p.m_particles_per_v);
      EXPECT_LE(result.mean_m_particles, p.m_particles_per_v);
    }
  }
  ASSERT_GT(converged_n, 100) << "too few converged V-particles to test";
  ASSERT_GT(spread_n, 100);
  const double converged_mean = converged_sum / converged_n, spread_mean = spread_sum / spread_n;
  std::cout << "[ kld      ] mean M-particles: converged V " << converged_mean << ", others " << spread_mean
            << ", fewest " << fewest << std::endl;
  // Measured, seed 1: converged 383, others 914, fewest 169 (243-295, 943-959, 105-144 over
  // seeds 1-3 with the importance-weighted proposals, proposal_correction 1).
  EXPECT_LT(converged_mean, 0.5 * spread_mean);
  EXPECT_LE(fewest, static_cast<std::size_t>(p.m_particles_per_v / 4));
}
}  // namespace
