// Context priors over the memory: per-label weights bias the
// M-particles' prototypes; a prototype of weight 0 has no M-particle at all.
#include <map>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/recognizer.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

amcr::Params smallParams()
{
  amcr::Params p;
  p.num_v_particles = 10;
  p.m_particles_per_prototype = 20;
  p.m_particles_per_v = 0;  // the paper's count per prototype, which the weights scale
  p.prototype_size = 64;
  p.seed = 3;
  return p;
}

std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const auto m = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, smallParams());
  return m;
}

cv::Mat frame()
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kStar, amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.3, 0.9, 0.9, 0.1)});
  return amcr_test::renderSequence(scene, 1)[0];
}

/// M-particles per prototype index over all V-particles.
std::map<int, int> countByPrototype(const amcr::Recognizer& recognizer)
{
  std::map<int, int> count;
  for (int p : recognizer.mParticles().prototype)
    ++count[p];
  return count;
}

TEST(Priors, WeightZeroCostsNothingAndNeverAppears)
{
  amcr::Params p = smallParams();
  p.prototype_priors = {{"crescent", 0.0}};
  amcr::Recognizer recognizer(p, memory());
  EXPECT_EQ(recognizer.mParticlesPerV(), 2 * p.m_particles_per_prototype);  // two active prototypes
  const cv::Mat image = frame();
  for (int k = 0; k < 25; ++k)  // past V-resampling, re-seeding and injection
  {
    recognizer.step(image);
    EXPECT_EQ(countByPrototype(recognizer).count(1), 0u) << "an M-particle of the crescent at step " << k;
  }
}

TEST(Priors, WeightsShareTheParticlesOfEachVParticle)
{
  amcr::Params p = smallParams();
  p.prototype_priors = {{"arrow", 2.0}, {"star", 1.0}};  // crescent: 1 (not listed)
  amcr::Recognizer recognizer(p, memory());
  ASSERT_EQ(recognizer.mParticlesPerV(), 3 * p.m_particles_per_prototype);
  std::map<int, int> slots;
  for (int prototype : recognizer.priorSlots())
    ++slots[prototype];
  EXPECT_EQ(slots[0], 30);
  EXPECT_EQ(slots[1], 15);
  EXPECT_EQ(slots[2], 15);
  // The first step seeds every V-particle's M-particles by those shares.
  recognizer.step(frame());
  EXPECT_EQ(static_cast<int>(recognizer.mParticles().size()), p.num_v_particles * 60);
}

// With a budget (m_particles_per_v) the weights share the budget, whatever
// the memory's size: 2:1:1 of 100 slots.
TEST(Priors, WeightsShareTheBudgetOfEachVParticle)
{
  amcr::Params p = smallParams();
  p.m_particles_per_v = 100;
  p.min_m_particles_per_v = 10;
  p.prototype_priors = {{"arrow", 2.0}, {"star", 1.0}};
  amcr::Recognizer recognizer(p, memory());
  ASSERT_EQ(recognizer.mParticlesPerV(), 100);
  std::map<int, int> slots;
  for (int prototype : recognizer.priorSlots())
    ++slots[prototype];
  EXPECT_EQ(slots[0], 50);
  EXPECT_EQ(slots[1], 25);
  EXPECT_EQ(slots[2], 25);
}

TEST(Priors, UnknownLabelOrAllZeroIsAParameterError)
{
  amcr::Params p = smallParams();
  p.prototype_priors = {{"kite", 1.0}};
  try
  {
    amcr::Recognizer recognizer(p, memory());
    ADD_FAILURE() << "no ParameterError for a label not in memory";
  }
  catch (const amcr::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find("kite"), std::string::npos) << e.what();
  }
  p.prototype_priors = {{"arrow", 0.0}, {"crescent", 0.0}, {"star", 0.0}};
  EXPECT_THROW(amcr::Recognizer(p, memory()), amcr::ParameterError);
}
}  // namespace
