// The proposal index (proposal_index.h): a V-particle's 8 feature rays find
// the (prototype, point, heading) places of the memory whose table rays look
// alike. Measured shares are in brackets beside each bound.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/filter/corrected_scan.h"
#include "amcr/base/errors.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/scan/radial_scan.h"
#include "candidate_lists.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kStride = 6;       // table px, the default index_stride
constexpr int kCandidates = 64;  // the default index_candidates

using amcr_test::binDistance;
using amcr_test::hits;

using amcr_test::tableRays;

class ProposalIndexTest : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    memory_ = amcr_test::drawnMemory(amcr_test::allShapes());
    index_ = std::make_unique<amcr::ProposalIndex>(*memory_, kStride);
  }
  static void TearDownTestSuite()
  {
    index_.reset();
    memory_.reset();
  }
  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
  static std::unique_ptr<amcr::ProposalIndex> index_;
};
std::shared_ptr<const amcr::PrototypeMemory> ProposalIndexTest::memory_;
std::unique_ptr<amcr::ProposalIndex> ProposalIndexTest::index_;

// Scans taken from a table at any pixel (not only the indexed ones) and any
// bin, at any scale: the true place is among the candidates.
TEST_F(ProposalIndexTest, FindsTheTablesOwnScansAtAnyScale)
{
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int tried = 0, found = 0;
  for (std::size_t p = 0; p < memory_->size(); ++p)
  {
    const amcr::Prototype& prototype = (*memory_)[p];
    for (int trial = 0; trial < 200; ++trial)
    {
      const cv::Point at = prototype.interior()[gen() % prototype.interior().size()];
      const int bin = static_cast<int>(gen() % amcr::kDirectionBins);
      const amcr::RaySignature s = tableRays(prototype, at.x, at.y, bin, static_cast<float>(0.4 + 2.6 * unit(gen)));
      if (s.valid_rays() < amcr::kFeatureRays)
        continue;
      ++tried;
      found += hits(index_->query(s, kCandidates), static_cast<int>(p), at, bin, 2.0 * kStride, 1) ? 1 : 0;
    }
  }
  ASSERT_GT(tried, 800);
  EXPECT_GE(found, 0.8 * tried) << found << " of " << tried;  // [0.88]
}

// The prototypes drawn into an image under random similarities and moderate
// affines (anisotropy up to 1.25, shear up to 0.1), scanned as a V-particle
// scans: the true place (within two strides and two bins) is among the
// candidates in most cases.
TEST_F(ProposalIndexTest, FindsDrawnShapesUnderSimilaritiesAndModerateAffines)
{
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const amcr::Params params;
  int tried_similar = 0, found_similar = 0, tried_affine = 0, found_affine = 0;
  for (ShapeId id : amcr_test::allShapes())
  {
    const int p = memory_->find(amcr_test::shapeName(id));
    const amcr::Prototype& prototype = (*memory_)[p];
    for (int view = 0; view < 8; ++view)
    {
      const bool affine = view % 2 == 1;
      const double rotation = 2.0 * M_PI * unit(gen);
      const double scale = 0.8 + 0.8 * unit(gen);  // image px per prototype-image px
      const double anisotropy = affine ? 1.1 + 0.15 * unit(gen) : 1.0;
      const double shear = affine ? 0.1 * (2.0 * unit(gen) - 1.0) : 0.0;
      const amcr::Affine to_image =
          amcr_test::makeAffine(amcr_test::prototypeCentre(), cv::Point2d(200, 200), rotation,
                                scale * std::sqrt(anisotropy), scale / std::sqrt(anisotropy), shear);
      cv::Mat image(400, 400, CV_8UC1, cv::Scalar(0));
      amcr_test::fillPolygon(image, amcr_test::transformPoints(to_image, amcr_test::shapePolygon(id)), 255);
      const amcr::RadialScanner scanner(amcr::prepareScanImage(image, params.blur_sigma), params.edge_threshold,
                                        params.max_ray_length);
      for (int trial = 0; trial < 40; ++trial)
      {
        const cv::Point table = prototype.interior()[gen() % prototype.interior().size()];
        const cv::Matx23d& back = prototype.tableToOriginal();
        const cv::Point2d original(back(0, 0) * table.x + back(0, 1) * table.y + back(0, 2),
                                   back(1, 0) * table.x + back(1, 1) * table.y + back(1, 2));
        const cv::Point2d at = amcr::applyAffine(to_image, original);
        const double heading = 2.0 * M_PI * unit(gen);
        amcr::RayHit rays[amcr::kFeatureRays];
        amcr::scanFeatureRays(scanner, static_cast<float>(at.x), static_cast<float>(at.y),
                              static_cast<float>(heading), rays);
        const amcr::RaySignature s = amcr::raySignature(rays);
        if (s.valid_rays() < amcr::kFeatureRays)
          continue;
        const int bin = amcr::angleToBin(heading - rotation);
        const bool hit = hits(index_->query(s, kCandidates), p, table, bin, 2.0 * kStride, 2);
        (affine ? tried_affine : tried_similar) += 1;
        (affine ? found_affine : found_similar) += hit ? 1 : 0;
      }
    }
  }
  ASSERT_GT(tried_similar, 300);
  ASSERT_GT(tried_affine, 300);
  EXPECT_GE(found_similar, 0.8 * tried_similar) << found_similar << " of " << tried_similar;  // [0.90]
  EXPECT_GE(found_affine, 0.8 * tried_affine) << found_affine << " of " << tried_affine;     // [0.91]
}

// Oblique views (anisotropy 2-3): the V-particle's own rays miss the true
// place mostly, the same place read under the view's shape
// (unsquashedFeatureRays) finds it as a frontal view is found.
TEST_F(ProposalIndexTest, FindsObliqueViewsReadUnderTheirViewShape)
{
  std::mt19937_64 gen(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const amcr::Params params;
  int tried = 0, found_own = 0, found_unsquashed = 0;
  for (ShapeId id : amcr_test::allShapes())
  {
    const int p = memory_->find(amcr_test::shapeName(id));
    const amcr::Prototype& prototype = (*memory_)[p];
    for (int view = 0; view < 4; ++view)
    {
      const double anisotropy = 2.0 + unit(gen);
      const double scale = 1.0 + 0.5 * unit(gen);
      const amcr::Affine to_image =
          amcr_test::makeAffine(amcr_test::prototypeCentre(), cv::Point2d(250, 250), 2.0 * M_PI * unit(gen),
                                scale * std::sqrt(anisotropy), scale / std::sqrt(anisotropy), 0.0);
      cv::Mat image(500, 500, CV_8UC1, cv::Scalar(0));
      amcr_test::fillPolygon(image, amcr_test::transformPoints(to_image, amcr_test::shapePolygon(id)), 255);
      const amcr::RadialScanner scanner(amcr::prepareScanImage(image, params.blur_sigma), params.edge_threshold,
                                        params.max_ray_length);
      // The image -> table map and its view shape.
      const amcr::Affine table_to_image = amcr::composeAffine(prototype.tableToOriginal(), to_image);
      amcr::Affine image_to_table;
      ASSERT_TRUE(amcr::invertAffine(table_to_image, image_to_table));
      const float linear[6] = {static_cast<float>(image_to_table(0, 0)), static_cast<float>(image_to_table(0, 1)), 0.f,
                               static_cast<float>(image_to_table(1, 0)), static_cast<float>(image_to_table(1, 1)), 0.f};
      float shape[3];
      ASSERT_TRUE(amcr::viewShape(linear, shape));
      for (int trial = 0; trial < 40; ++trial)
      {
        const cv::Point table = prototype.interior()[gen() % prototype.interior().size()];
        const cv::Point2d at = amcr::applyAffine(table_to_image, cv::Point2d(table));
        const double heading = 2.0 * M_PI * unit(gen);
        amcr::RayHit rays[amcr::kFeatureRays];
        amcr::scanFeatureRays(scanner, static_cast<float>(at.x), static_cast<float>(at.y),
                              static_cast<float>(heading), rays);
        const amcr::RaySignature own = amcr::raySignature(rays);
        const amcr::RaySignature unsquashed = amcr::unsquashedFeatureRays(
            scanner, static_cast<float>(at.x), static_cast<float>(at.y), static_cast<float>(heading), shape);
        if (own.valid_rays() < amcr::kFeatureRays || unsquashed.valid_rays() < amcr::kFeatureRays)
          continue;
        // The true heading: the table direction of the V-particle's heading.
        const double tx = linear[0] * std::cos(heading) + linear[1] * std::sin(heading);
        const double ty = linear[3] * std::cos(heading) + linear[4] * std::sin(heading);
        const int bin = amcr::angleToBin(std::atan2(ty, tx));
        ++tried;
        found_own += hits(index_->query(own, kCandidates), p, table, bin, 2.0 * kStride, 2) ? 1 : 0;
        found_unsquashed += hits(index_->query(unsquashed, kCandidates), p, table, bin, 2.0 * kStride, 2) ? 1 : 0;
      }
    }
  }
  ASSERT_GT(tried, 300);
  EXPECT_LT(found_own, 0.5 * tried) << found_own << " of " << tried;                // [0.24]
  EXPECT_GE(found_unsquashed, 0.8 * tried) << found_unsquashed << " of " << tried;  // [0.87]
  std::cout << "[ oblique  ] own rays " << found_own << " of " << tried << ", unsquashed " << found_unsquashed
            << std::endl;
}

// The k-d tree search against the exhaustive reference on the same
// queries: the same k nearest (up to ties), and the nearest found is never
// nearer than the exact nearest (it is a true distance).
TEST_F(ProposalIndexTest, TreeSearchAgreesWithExhaustiveSearch)
{
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int exact_total = 0, shared_total = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    const amcr::Prototype& prototype = (*memory_)[gen() % memory_->size()];
    const cv::Point at = prototype.interior()[gen() % prototype.interior().size()];
    amcr::RaySignature s =
        tableRays(prototype, at.x, at.y, static_cast<int>(gen() % amcr::kDirectionBins), 1.3f);
    for (float& d : s.distance)
      d *= static_cast<float>(std::exp(0.2 * (2.0 * unit(gen) - 1.0)));  // not an indexed point
    amcr::RayDescriptor described;
    if (!amcr::describeRays(s, described))
      continue;  // an incomplete scan, or a ray shorter than 2 px
    const auto approx = index_->query(s, kCandidates);
    const auto exact = index_->queryExact(s, kCandidates);
    ASSERT_EQ(exact.size(), static_cast<std::size_t>(kCandidates));
    ASSERT_FALSE(approx.empty());
    EXPECT_GE(approx.front().distance, exact.front().distance - 1e-4f);
    for (const auto& e : exact)
    {
      ++exact_total;
      for (const auto& a : approx)
        if (a.prototype == e.prototype && a.x == e.x && a.y == e.y && a.bin == e.bin)
        {
          ++shared_total;
          break;
        }
    }
  }
  ASSERT_GT(exact_total, 1000);
  EXPECT_GE(shared_total, 0.98 * exact_total) << shared_total << " of " << exact_total;  // [0.999]
}

// A memory too large for index_max_entries is indexed at a larger
// stride, with a warning, and still finds the tables' own scans.
TEST_F(ProposalIndexTest, AnEntryBudgetRaisesTheStride)
{
  const std::size_t budget = index_->size() / 3;
  std::vector<std::string> warnings;
  const amcr::ProposalIndex small(*memory_, kStride, {}, [&](const std::string& line) { warnings.push_back(line); },
                                  nullptr, budget);
  EXPECT_LE(small.size(), budget);
  EXPECT_GT(small.size(), budget / 4);  // the smallest stride that fits, not any
  EXPECT_GT(small.stride(), kStride);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("index_max_entries"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("stride " + std::to_string(small.stride())), std::string::npos) << warnings[0];
  // A budget the memory fits changes nothing.
  const amcr::ProposalIndex same(*memory_, kStride, {}, {}, nullptr, index_->size());
  EXPECT_EQ(same.size(), index_->size());
  EXPECT_EQ(same.stride(), kStride);
  // The places it keeps are still found: a scan from the table at an indexed place.
  const amcr::Prototype& p = (*memory_)[2];
  int found = 0, tried = 0;
  for (const cv::Point& at : p.interior())
  {
    if (at.x % small.stride() != 0 || at.y % small.stride() != 0 || tried >= 20)
      continue;
    const amcr::RaySignature rays = amcr_test::tableRays(p, at.x, at.y, 10, 1.0f);
    const std::vector<amcr::ProposalCandidate> c = small.query(rays, 8);
    if (c.empty())
      continue;
    ++tried;
    found += std::any_of(c.begin(), c.end(), [&](const amcr::ProposalCandidate& k) {
      return k.prototype == 2 && std::abs(k.x - at.x) <= 1 && std::abs(k.y - at.y) <= 1;
    });
  }
  ASSERT_GT(tried, 5);
  EXPECT_GE(found, tried * 8 / 10) << found << " of " << tried;
}

// A memory larger than the sample the stride is chosen from (130 > 64
// prototypes): the entries fit the budget, and the stride is the smallest
// that fits or close to it.
TEST(ProposalIndexBudget, ALargeMemoryFitsFromTheSampledStride)
{
  amcr::Params params;
  params.prototype_size = 48;
  amcr::PrototypeMemory memory;
  for (std::uint64_t k = 0; k < 130; ++k)
    memory.add("shape" + std::to_string(k), amcr_test::drawRandomSilhouette(k + 1), params);
  const amcr::ProposalIndex full(memory, 2);
  const std::size_t budget = full.size() / 5;
  std::vector<std::string> warnings;
  const amcr::ProposalIndex capped(memory, 2, {}, [&](const std::string& line) { warnings.push_back(line); }, nullptr,
                                   budget);
  EXPECT_LE(capped.size(), budget);
  EXPECT_GT(capped.size(), budget / 3) << "stride " << capped.stride();
  EXPECT_GE(capped.stride(), 4);  // sqrt(5) x 2, rounded up
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("index_max_entries"), std::string::npos) << warnings[0];
}

TEST_F(ProposalIndexTest, AnIncompleteScanProposesNothing)
{
  amcr::RaySignature s;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    s.distance[k] = 10.f + k;
  s.distance[3] = 0.f;  // one ray met no edge
  EXPECT_TRUE(index_->query(s, kCandidates).empty());
  EXPECT_TRUE(index_->query(amcr::RaySignature(), kCandidates).empty());
}

TEST_F(ProposalIndexTest, TheDescriptorIgnoresScale)
{
  amcr::RaySignature s;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    s.distance[k] = 5.f + 3.f * k;
  amcr::RaySignature twice = s;
  for (float& d : twice.distance)
    d *= 2.f;
  amcr::RayDescriptor a, b;
  ASSERT_TRUE(amcr::describeRays(s, a));
  ASSERT_TRUE(amcr::describeRays(twice, b));
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    EXPECT_NEAR(a[k], b[k], 1e-5);
  const auto near = index_->query(s, 1), near_twice = index_->query(twice, 1);
  ASSERT_EQ(near.size(), 1u);
  ASSERT_EQ(near_twice.size(), 1u);
  EXPECT_EQ(near[0].x, near_twice[0].x);
  EXPECT_NEAR(near[0].log_scale - near_twice[0].log_scale, std::log(2.0), 1e-4);
}

/// A disc filling its image: at prototype_size 512 every pixel of it has a
/// ray longer than the table holds (127 px), so no place has 8 rays.
cv::Mat discImage()
{
  cv::Mat image(200, 200, CV_8UC1, cv::Scalar(0));
  cv::circle(image, {100, 100}, 95, cv::Scalar(255), cv::FILLED);
  return image;
}

amcr::Params largeTables()
{
  amcr::Params params;
  params.prototype_size = 512;
  return params;
}

TEST(ProposalIndexBadInput, APrototypeWithoutPlacesIsNamedAndLeftOut)
{
  amcr::PrototypeMemory memory;
  memory.add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), amcr::Params());
  memory.add("disc", discImage(), largeTables());
  std::vector<std::string> warnings;
  const amcr::ProposalIndex index(memory, 6, {}, [&](const std::string& line) { warnings.push_back(line); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'disc'"), std::string::npos) << warnings[0];
  ASSERT_EQ(index.leftOut(), std::vector<std::string>{"disc"});
  EXPECT_GT(index.size(), 500u);  // the arrow is indexed
}

// A small prototype (prototype_size 32) has too few places at the default
// stride and is indexed at a finer one.
TEST(ProposalIndexBadInput, ASmallPrototypeIsIndexedAtAFinerStride)
{
  amcr::Params small;
  small.prototype_size = 32;
  amcr::PrototypeMemory memory;
  memory.add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), small);
  std::vector<std::string> warnings;
  const amcr::ProposalIndex index(memory, 6, {}, [&](const std::string& line) { warnings.push_back(line); });
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(index.leftOut().empty());
  EXPECT_GT(index.size(), 100u);
}

TEST(ProposalIndexBadInput, AnIndexWithoutUsableEntriesIsAnError)
{
  amcr::PrototypeMemory memory;
  memory.add("disc", discImage(), largeTables());
  EXPECT_THROW(amcr::ProposalIndex(memory, 6), amcr::MemoryError);
  EXPECT_THROW(amcr::ProposalIndex(memory, 0), amcr::ParameterError);
}
}  // namespace
