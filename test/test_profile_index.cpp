// The radial-profile index (profile_index.h): a V-particle's 72-ray profile,
// keyed by its Fourier magnitudes and aligned for the heading, finds its true
// place. On drawn shapes over clutter; the measured shares are in brackets
// beside each bound, and the 8-ray index's on the same points beside them.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/filter/profile_index.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/scan/radial_scan.h"
#include "candidate_lists.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kStride = 3;       // table px: half the default index_stride, as the filter builds it
constexpr int kSearch = 64;      // the default index_candidates
constexpr int kKeep = 8;         // ParticleSeeder::kProfileCandidates
constexpr double kRadius = 2.0 * kStride;  // table px from the true place that still counts as it

using amcr_test::binDistance;
using amcr_test::hits;

class ProfileIndexTest : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    memory_ = amcr_test::drawnMemory(amcr_test::allShapes());
    index_ = std::make_unique<amcr::ProfileIndex>(*memory_, kStride);
  }
  static void TearDownTestSuite()
  {
    index_.reset();
    memory_.reset();
  }
  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
  static std::unique_ptr<amcr::ProfileIndex> index_;
};
std::shared_ptr<const amcr::PrototypeMemory> ProfileIndexTest::memory_;
std::unique_ptr<amcr::ProfileIndex> ProfileIndexTest::index_;

// A table's own profile, turned by whole bins and scaled: the key stays
// (rotation and scale free), the alignment finds the turn, the means the scale.
TEST_F(ProfileIndexTest, TheKeyIgnoresRotationAndScaleAndTheAlignmentFindsTheTurn)
{
  std::mt19937_64 gen(3);
  int tried = 0;
  for (std::size_t p = 0; p < memory_->size(); ++p)
  {
    const amcr::Prototype& prototype = (*memory_)[p];
    for (int trial = 0; trial < 50; ++trial)
    {
      const cv::Point at = prototype.interior()[gen() % prototype.interior().size()];
      amcr::RadialProfile table;
      if (!amcr::tableProfile(prototype, at.x, at.y, table))
        continue;
      const int turn = static_cast<int>(gen() % amcr::kDirectionBins);
      const float scale = 1.f + static_cast<float>(gen() % 100) / 40.f;  // 1-3.5: no ray below 2 px
      float distance[amcr::kDirectionBins];
      for (int k = 0; k < amcr::kDirectionBins; ++k)
        distance[k] = scale * std::exp(table.log_mean + table.centred[(k + turn) % amcr::kDirectionBins]);
      amcr::RadialProfile seen;
      ASSERT_TRUE(amcr::makeProfile(distance, seen));
      const amcr::ProfileKey a = amcr::profileKey(table), b = amcr::profileKey(seen);
      for (int m = 0; m < amcr::kProfileHarmonics; ++m)
        EXPECT_NEAR(a[m], b[m], 1e-4) << "harmonic " << m + 1;
      float error = 1.f;
      EXPECT_EQ(amcr::alignProfiles(seen, table, error), turn);
      EXPECT_LT(error, 1e-8);
      EXPECT_NEAR(table.log_mean - seen.log_mean, -std::log(scale), 1e-4);
      ++tried;
    }
  }
  EXPECT_GT(tried, 200);
}

// Each drawn shape over clutter (random shapes, lines, a gradient, noise)
// under a random similarity, scanned as a V-particle scans from interior
// points: the true place (within two strides and two bins) is among the best
// kKeep aligned candidates.
TEST_F(ProfileIndexTest, FindsDrawnShapesOverClutterAmongTheBestAligned)
{
  std::mt19937_64 gen(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const amcr::Params params;
  const amcr::ProposalIndex rays8(*memory_, 2 * kStride);
  int tried = 0, found = 0, first = 0, found8 = 0;
  for (ShapeId id : amcr_test::allShapes())
  {
    const int p = memory_->find(amcr_test::shapeName(id));
    const amcr::Prototype& prototype = (*memory_)[p];
    for (int view = 0; view < 3; ++view)
    {
      const double rotation = 2.0 * M_PI * unit(gen);
      const double scale = 0.7 + 0.6 * unit(gen);
      amcr_test::Scene scene;
      scene.objects.push_back({id, amcr_test::makeAffine(amcr_test::prototypeCentre(), cv::Point2d(320, 240), rotation,
                                                         scale, scale, 0.0)});
      scene.clutter.seed = 100 + 10 * static_cast<std::uint64_t>(id) + static_cast<std::uint64_t>(view);
      const cv::Mat image = amcr_test::renderSequence(scene, 1)[0];
      const cv::Mat scan = amcr::prepareScanImage(image, params.blur_sigma);
      const amcr::RadialScanner scanner(
          scan, amcr::EdgeThresholds(scan, params.edge_threshold, params.edge_full_strength), params.max_ray_length);
      const amcr::Affine table_to_image =
          amcr::composeAffine(prototype.tableToOriginal(), scene.objects[0].prototype_to_image);
      for (int trial = 0; trial < 60; ++trial)
      {
        const cv::Point table = prototype.interior()[gen() % prototype.interior().size()];
        const cv::Point2d at = amcr::applyAffine(table_to_image, cv::Point2d(table));
        const double heading = 2.0 * M_PI * unit(gen);
        amcr::RadialProfile profile;
        if (!amcr::scanProfile(scanner, static_cast<float>(at.x), static_cast<float>(at.y),
                               static_cast<float>(heading), profile))
          continue;
        ++tried;
        const int bin = amcr::angleToBin(heading - rotation);
        const std::vector<amcr::ProposalCandidate> best = index_->query(*memory_, profile, kSearch, kKeep);
        found += hits(best, p, table, bin, kRadius, 2) ? 1 : 0;
        first += !best.empty() && hits({best[0]}, p, table, bin, kRadius, 2) ? 1 : 0;
        amcr::RayHit rays[amcr::kFeatureRays];
        amcr::scanFeatureRays(scanner, static_cast<float>(at.x), static_cast<float>(at.y),
                              static_cast<float>(heading), rays);
        found8 += hits(rays8.query(amcr::raySignature(rays), kKeep), p, table, bin, kRadius, 2) ? 1 : 0;
      }
    }
  }
  std::cout << "[ profile  ] " << tried << " points: true place among the best " << kKeep << " aligned in " << found
            << ", first in " << first << "; the 8-ray index's first " << kKeep << " in " << found8 << std::endl;
  ASSERT_GT(tried, 600);
  EXPECT_GE(found, 0.85 * tried) << found << " of " << tried;  // [0.91; first alone 0.75; the 8-ray index 0.68]
  EXPECT_GT(found, found8) << "the profile index finds no more than the 8-ray index";
}

TEST(ProfileIndexBadInput, AProfileOfTooFewEdgesIsRefused)
{
  float distance[amcr::kDirectionBins];
  std::fill(distance, distance + amcr::kDirectionBins, 20.f);
  for (int k = 0; k <= amcr::kMaxMissingProfileRays; ++k)
    distance[3 * k] = 0.f;  // one miss more than allowed
  amcr::RadialProfile profile;
  EXPECT_FALSE(amcr::makeProfile(distance, profile));
  distance[0] = 20.f;  // as many as allowed: filled from the neighbours
  ASSERT_TRUE(amcr::makeProfile(distance, profile));
  for (float c : profile.centred)
    EXPECT_NEAR(c, 0.f, 1e-5);
  distance[1] = 1.f;  // on an edge
  EXPECT_FALSE(amcr::makeProfile(distance, profile));
}

TEST(ProfileIndexBadInput, AStrideBelowOneIsRefused)
{
  const auto memory = amcr_test::drawnMemory({ShapeId::kArrow});
  EXPECT_THROW(amcr::ProfileIndex(*memory, 0), amcr::ParameterError);
}
}  // namespace
