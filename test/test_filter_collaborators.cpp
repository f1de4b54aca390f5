// The particle filter's collaborators on their own (particle_filter.h): the
// held objects (inhibition of return, the scene's context), the resampler's
// draw of the next V-particles, the attention control's policy and the
// seeder's new particles, each without a ParticleFilter around it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/filter/attention_control.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/held_objects.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particle_seeder.h"
#include "amcr/filter/resampler.h"
#include "amcr/scan/radial_scan.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

const cv::Size kImage(320, 240);

/// A held object whose outline is the box [x0, x1] x [y0, y1].
amcr::HeldObject heldBox(int prototype, double x0, double y0, double x1, double y1, std::vector<int> v = {})
{
  return amcr::HeldObject{prototype, {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, std::move(v)};
}

std::shared_ptr<const amcr::PrototypeMemory> twoShapes()
{
  static const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent});
  return memory;
}

TEST(HeldObjects, APrototypeOutsideTheMemoryIsRefusedAndNothingChanges)
{
  const amcr::Params params;
  const amcr::PrototypePrior prior(*twoShapes(), params);
  amcr::HeldObjects held(params);
  held.set({heldBox(0, 10, 10, 50, 50)}, kImage, prior, 2);
  EXPECT_THROW(held.set({heldBox(2, 100, 100, 150, 150)}, kImage, prior, 2), amcr::InputError);
  EXPECT_THROW(held.set({heldBox(-1, 100, 100, 150, 150)}, kImage, prior, 2), amcr::InputError);
  EXPECT_EQ(held.at(30, 30), 0);  // the first set still holds
  EXPECT_EQ(held.at(120, 120), -1);
}

TEST(HeldObjects, APlaceIsInsideTheHullOfTheObjectThatHoldsIt)
{
  const amcr::Params params;
  const amcr::PrototypePrior prior(*twoShapes(), params);
  amcr::HeldObjects held(params);
  held.set({heldBox(0, 10, 10, 50, 50), heldBox(1, 200, 100, 300, 200)}, kImage, prior, 2);
  EXPECT_EQ(held.at(30, 30), 0);
  EXPECT_EQ(held.at(250, 150), 1);
  EXPECT_EQ(held.at(100, 100), -1);
  EXPECT_EQ(held.at(-5, 30), -1);   // outside the image
  EXPECT_EQ(held.at(30, 1000), -1);
  held.clear();
  EXPECT_EQ(held.at(30, 30), -1);
}

TEST(HeldObjects, NewPlacesAvoidTheHeldObjects)
{
  const amcr::Params params;
  const amcr::PrototypePrior prior(*twoShapes(), params);
  amcr::HeldObjects held(params);
  // Nearly the whole image held but a strip at the right: the uniform draws
  // mostly fail, and the free pixels must be found.
  held.set({heldBox(0, 0, 0, 300, 239)}, kImage, prior, 2);
  amcr::Rng rng(7);
  for (int k = 0; k < 200; ++k)
  {
    const cv::Point2f place = held.drawFreePlace(kImage, rng);
    ASSERT_EQ(held.at(place.x, place.y), -1) << place;
    EXPECT_GT(place.x, 300.f);
  }
}

TEST(HeldObjects, TheSeedingLeansTowardsTheHeldPrototypesByTheSceneShare)
{
  amcr::Params params;
  params.scene_prior_share = 0.25;
  const amcr::PrototypePrior prior(*twoShapes(), params);  // 1/2 each
  amcr::HeldObjects held(params);
  EXPECT_DOUBLE_EQ(held.seedingProbability(1, prior), 0.5);  // nothing held: the prior
  held.set({heldBox(1, 10, 10, 50, 50)}, kImage, prior, 2);
  EXPECT_DOUBLE_EQ(held.seedingProbability(1, prior), 0.75 * 0.5 + 0.25);
  EXPECT_DOUBLE_EQ(held.seedingProbability(0, prior), 0.75 * 0.5);
  amcr::Rng rng(3);
  int held_prototype = 0;
  const int draws = 20000;
  for (int k = 0; k < draws; ++k)
    held_prototype += held.scenePrototype(0, rng) == 1 ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(held_prototype) / draws, 0.25, 0.02);
}

TEST(HeldObjects, EachKeepsItsBestVParticlesAndTheRestAreNotDrawn)
{
  amcr::Params params;
  params.held_v_particles = 2;
  const amcr::PrototypePrior prior(*twoShapes(), params);
  amcr::HeldObjects held(params);
  // V-particles 0-3 inside the object, 4 supports it from outside, 5-9 free.
  std::vector<amcr::VParticle> v(10);
  for (int i = 0; i < 10; ++i)
  {
    v[i].x = i < 4 ? 20.f + i : 200.f + i;
    v[i].y = 30.f;
  }
  held.set({heldBox(0, 10, 10, 50, 50, {4})}, kImage, prior, 2);
  std::vector<double> log_weights = {-5, -1, -3, -4, -2, 0, 0, 0, 0, 0};
  const std::vector<int> kept = held.keep(v, log_weights);
  EXPECT_EQ(kept, (std::vector<int>{1, 4}));  // the best two of 0-4, in index order
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(log_weights[i], -std::numeric_limits<double>::infinity()) << i;
  for (int i = 5; i < 10; ++i)
    EXPECT_EQ(log_weights[i], 0.0) << i;
}

TEST(Resampler, TheKeptVParticlesComeFirstAndNoneIsCopiedMoreThanThreeTimes)
{
  amcr::Params params;
  params.held_v_particles = 1;
  params.v_reseed_fraction = 0.0;
  const amcr::PrototypePrior prior(*twoShapes(), params);
  amcr::HeldObjects held(params);
  std::vector<amcr::VParticle> v(12);
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    v[i].x = i == 0 ? 20.f : 200.f;
    v[i].y = 30.f;
    v[i].evidence_count = 1;
    v[i].log_evidence_sum = i == 5 ? 0.0 : -50.0;  // V-particle 5 carries nearly all the weight
  }
  held.set({heldBox(0, 10, 10, 50, 50)}, kImage, prior, 2);
  amcr::Resampler resampler(params, params, params, params.seed);
  const amcr::VGeneration next = resampler.drawV(v, {}, held);
  ASSERT_EQ(next.source.size(), v.size());
  EXPECT_EQ(next.source[0], 0);  // the one on the held object, carried over
  EXPECT_FALSE(next.turned[0]);
  EXPECT_EQ(std::count(next.source.begin(), next.source.end(), 5), 3);
  EXPECT_EQ(std::count(next.source.begin(), next.source.end(), -1), 8);  // the rest seeded afresh
  int first_copy = -1;
  for (std::size_t k = 0; k < next.source.size(); ++k)
    if (next.source[k] == 5)
    {
      EXPECT_EQ(next.turned[k], first_copy >= 0) << k;  // only later copies turn
      first_copy = first_copy < 0 ? static_cast<int>(k) : first_copy;
    }

  // Same seed, same draw; reset starts the stream again.
  amcr::Resampler again(params, params, params, params.seed);
  EXPECT_EQ(again.drawV(v, {}, held).source, next.source);
  resampler.reset(params.seed);
  EXPECT_EQ(resampler.drawV(v, {}, held).source, next.source);
}

class PolicyGoingLeft : public amcr::ExplorationPolicy
{
public:
  amcr::Control decide(const amcr::VParticle&, const amcr::RadialScanner&, amcr::Rng&) const override
  {
    return amcr::Control{M_PI, 3.0};
  }
};

TEST(AttentionControl, ThePolicyMovesAVParticleThatDecidesNothing)
{
  amcr::Params params;
  params.discriminative_moves = false;
  params.competing_fits = 0;
  const amcr::FilterMemory memory(params, twoShapes());
  amcr::AttentionControl attention(params, params, params);
  EXPECT_THROW(attention.setPolicy(nullptr), amcr::ParameterError);
  attention.setPolicy(std::make_unique<PolicyGoingLeft>());
  const cv::Mat image(kImage, CV_8UC1, cv::Scalar(0));
  const amcr::RadialScanner scanner(image, params.edge_threshold, params.max_ray_length);
  amcr::VParticle v;
  v.x = 100.f;
  v.y = 100.f;
  amcr::MParticleSet m;
  m.resize(4);
  amcr::Rng rng(1);
  const amcr::ObservationModel observation(params);
  const amcr::Control u = attention.decide(v, m, amcr::MRange{0, 4}, memory, observation, kImage, scanner, rng);
  EXPECT_DOUBLE_EQ(u.rotation, M_PI);
  EXPECT_DOUBLE_EQ(u.translation, 3.0);
  EXPECT_FALSE(v.discriminating);
  EXPECT_EQ(v.competing.count, 0);
}

TEST(ParticleSeeder, NewParticlesStartOutsideTheHeldObjectsAndInsideTheirPrototypes)
{
  amcr::Params params;
  params.m_particles_per_v = 200;
  const amcr::FilterMemory memory(params, twoShapes());
  const amcr::PrototypePrior& prior = memory.prior();
  amcr::HeldObjects held(params);
  held.set({heldBox(0, 0, 0, 200, 239)}, kImage, prior, 2);  // the left part of the image is explained
  cv::Mat image(kImage, CV_8UC1, cv::Scalar(30));
  cv::rectangle(image, cv::Rect(220, 60, 60, 100), cv::Scalar(220), cv::FILLED);
  const cv::Mat scan = amcr::prepareScanImage(image, params.blur_sigma);
  const amcr::RadialScanner scanner(scan, params.edge_threshold, params.max_ray_length);
  const amcr::ObservationModel observation(params);
  const amcr::ParticleSeeder seeder(params, params, params, observation.logInvalid());
  const amcr::SeedingScene scene{memory, held, kImage};
  const std::size_t count = prior.slots().size();
  amcr::MParticleSet m;
  m.resize(count);
  amcr::VWorkspace work(amcr::Rng(5));
  for (int trial = 0; trial < 20; ++trial)
  {
    amcr::VParticle v;
    seeder.seedVAndM(v, m, 0, count, scanner, scene, work);
    EXPECT_EQ(held.at(v.x, v.y), -1) << v.x << ", " << v.y;
    for (std::size_t i = 0; i < count; ++i)
    {
      ASSERT_GE(m.prototype[i], 0);
      ASSERT_LT(m.prototype[i], 2);
      const amcr::Prototype& p = (*memory.memory())[m.prototype[i]];
      EXPECT_GE(m.x[i], 0.f);
      EXPECT_GE(m.y[i], 0.f);
      EXPECT_LE(m.x[i], p.width() - 1.f);
      EXPECT_LE(m.y[i], p.height() - 1.f);
      EXPECT_EQ(m.affine_valid[i], amcr::kNoAffine);  // measured later
    }
  }
}

// A V-particle placed where the image proposes an object (coverage_schedule.h)
// is seeded there, and its M-particles are seeded and weighted as any new
// V-particle's: the index draws most of them in the prototype it sees, and
// with proposal_correction 1 their importance weights give each prototype
// back its prior share (the filter's posterior stays the paper's).
TEST(ParticleSeeder, AVParticleAtAnImagePlaceKeepsTheMixtureWeights)
{
  amcr::Params params;
  params.m_particles_per_v = 400;
  params.index_share = 0.5;
  params.proposal_correction = 1.0;
  const amcr::FilterMemory memory(params, twoShapes());
  ASSERT_TRUE(memory.index());
  amcr::HeldObjects held(params);
  const cv::Mat image = amcr_test::drawPrototype(ShapeId::kArrow);  // the arrow seen as it is stored
  const cv::Mat scan = amcr::prepareScanImage(image, params.blur_sigma);
  const amcr::RadialScanner scanner(scan, params.edge_threshold, params.max_ray_length);
  const amcr::ObservationModel observation(params);
  const amcr::ParticleSeeder seeder(params, params, params, observation.logInvalid());
  const amcr::SeedingScene scene{memory, held, image.size()};
  const std::size_t count = memory.prior().slots().size();
  // The place deepest inside the arrow: all its rays meet the arrow's outline.
  cv::Point2d centre;
  float deepest = 0.f;
  for (std::size_t k = 0; k < (*memory.memory())[0].interior().size(); k += 7)
  {
    const cv::Point2f at((*memory.memory())[0].interior()[k]);
    const cv::Point2d in_image(at.x * image.cols / (*memory.memory())[0].width(),
                               at.y * image.rows / (*memory.memory())[0].height());
    amcr::RayHit hits[amcr::kFeatureRays];
    amcr::scanFeatureRays(scanner, static_cast<float>(in_image.x), static_cast<float>(in_image.y), 0.f, hits);
    float shortest = std::numeric_limits<float>::infinity();
    for (const amcr::RayHit& hit : hits)
      shortest = std::min(shortest, hit.valid ? hit.distance : 0.f);
    if (shortest > deepest)
    {
      deepest = shortest;
      centre = in_image;
    }
  }
  ASSERT_GT(deepest, 4.f) << "no place inside the drawn arrow sees its outline all round";
  amcr::MParticleSet m;
  m.resize(count);
  amcr::VWorkspace work(amcr::Rng(11));
  double drawn_arrow = 0.0, drawn = 0.0, weighted_arrow = 0.0, weighted = 0.0;
  for (int turn = 0; turn < 8; ++turn)
  {
    const amcr::RayPlace place{static_cast<float>(centre.x), static_cast<float>(centre.y),
                               static_cast<float>(turn * M_PI / 4.0)};
    amcr::VParticle v;
    seeder.seedVAndMAt(place, v, m, 0, count, scanner, scene, work);
    EXPECT_EQ(v.x, place.x);
    EXPECT_EQ(v.y, place.y);
    EXPECT_EQ(v.theta, place.theta);
    EXPECT_EQ(v.rays.valid_rays(), amcr::kFeatureRays);  // read where it stands
    for (std::size_t i = 0; i < count; ++i)
    {
      const double w = std::exp(static_cast<double>(m.log_proposal[i]));
      drawn += 1.0;
      weighted += w;
      if (m.prototype[i] == 0)
      {
        drawn_arrow += 1.0;
        weighted_arrow += w;
      }
    }
  }
  // The index proposes the arrow: most particles are drawn in it...
  EXPECT_GT(drawn_arrow / drawn, 0.6);
  // ...and the weights give it back its prior share, a half.
  EXPECT_NEAR(weighted_arrow / weighted, 0.5, 0.05);  // 0.65 unweighted, 0.5 within 0.01 measured
}
}  // namespace
