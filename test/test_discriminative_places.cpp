// Discriminative places, precomputed (discriminative_places.h): the
// look-alike pairs the index confuses, their alignment, the places where
// their scans differ, and those places in the table cache.
#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/discriminative_places_cache.h"
#include "amcr/base/errors.h"
#include "amcr/filter/observation_model.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_alignment.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/base/random.h"
#include "amcr/memory/table_cache.h"
#include "scene_drawing.h"

namespace
{
constexpr int kBird = 0;
constexpr int kCrested = 1;
constexpr int kStar = 2;

std::shared_ptr<const amcr::PrototypeMemory> birdsAndStar(const amcr::Params& params)
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("bird", amcr_test::drawSilhouette(amcr_test::drawnBird(false)), params);
  memory->add("crested", amcr_test::drawSilhouette(amcr_test::drawnBird(true)), params);
  memory->add("star", amcr_test::drawPrototype(amcr_test::ShapeId::kStar), params);
  return memory;
}

/// The drawn bird, the crested bird and a star, and the observation model
/// the places are measured in.
class DiscriminativePlacesTest : public ::testing::Test
{
protected:
  amcr::DiscriminativePlaces build() const
  {
    return amcr::DiscriminativePlaces::build(*memory, observation, amcr::DiscriminativePlacesSettings());
  }

  const amcr::Params params{};
  const std::shared_ptr<const amcr::PrototypeMemory> memory = birdsAndStar(params);
  const amcr::ObservationModel observation{params};
};

cv::Point2d toTable(const amcr::Prototype& p, cv::Point2d original)
{
  return amcr::applyAffine(p.originalToTable(), original);
}

/// The table -> table map of two prototypes drawn `original_a_to_b` apart
/// in their images.
amcr::Affine tableToTable(const amcr::Prototype& a, const amcr::Prototype& b, const amcr::Affine& original_a_to_b)
{
  return amcr::composeAffine(amcr::composeAffine(a.tableToOriginal(), original_a_to_b), b.originalToTable());
}

double distance(cv::Point2d p, cv::Point2d q) { return std::hypot(p.x - q.x, p.y - q.y); }

// A bird and the same bird turned by 35 deg and shrunk to 0.8 in its image:
// from 30 true corresponding places and 10 wrong ones, the alignment maps
// every outline point of the first within 1.5 table px of where the truth
// puts it. A shape that is not alike is refused.
TEST(PrototypeAlignment, RecoversATurnedShrunkCopyDespiteWrongPlaces)
{
  amcr::Params params;
  const cv::Point2d centre(100, 100);
  const amcr::Affine turn = amcr_test::makeAffine(centre, centre, 35.0 * M_PI / 180.0, 0.8, 0.8, 0.0);
  amcr::PrototypeMemory memory;
  memory.add("bird", amcr_test::drawSilhouette(amcr_test::drawnBird(false)), params);
  memory.add("turned", amcr_test::drawSilhouette(amcr_test::transformPoints(turn, amcr_test::drawnBird(false))),
             params);
  memory.add("star", amcr_test::drawPrototype(amcr_test::ShapeId::kStar), params);
  const amcr::Prototype& a = memory[0];
  const amcr::Prototype& b = memory[1];
  const amcr::Affine truth = tableToTable(a, b, turn);

  amcr::Rng rng(7);
  std::vector<cv::Point2d> in_a, in_b;
  for (int i = 0; i < 40; ++i)
  {
    const cv::Point& p = a.interior()[rng.index(a.interior().size())];
    in_a.emplace_back(p.x, p.y);
    const bool wrong = i % 4 == 3;
    // One draw per statement (a call's arguments come in no set order), the second coordinate first.
    const double second = wrong ? rng.uniform(0.0, b.height()) : rng.gaussian(1.0);
    const double first = wrong ? rng.uniform(0.0, b.width()) : rng.gaussian(1.0);
    in_b.push_back(wrong ? cv::Point2d(first, second)
                         : amcr::applyAffine(truth, in_a.back()) + cv::Point2d(first, second));
  }
  amcr::PrototypeAlignment alignment;
  ASSERT_TRUE(amcr::alignPrototypes(a, b, in_a, in_b, 5.0, 6, 8.0, alignment));
  EXPECT_GE(alignment.inliers, 28);
  EXPECT_LT(alignment.outline_distance, 1.0);
  double worst = 0.0;
  for (const amcr::OutlinePoint& p : a.outline())
    worst = std::max(worst, distance(amcr::applyAffine(alignment.a_to_b, cv::Point2d(p.position)),
                                     amcr::applyAffine(truth, cv::Point2d(p.position))));
  EXPECT_LT(worst, 1.5) << "table px of the turned bird";

  // The star is no look-alike: even with places that agree on a similarity,
  // its outline stays far from the bird's.
  std::vector<cv::Point2d> in_star;
  for (const cv::Point2d& p : in_a)
    in_star.push_back(p);
  EXPECT_FALSE(amcr::alignPrototypes(a, memory[2], in_a, in_star, 5.0, 6, 8.0, alignment));
  // Too few places.
  EXPECT_FALSE(amcr::alignPrototypes(a, b, {in_a.begin(), in_a.begin() + 3}, {in_b.begin(), in_b.begin() + 3}, 5.0,
                                     6, 8.0, alignment));
}

// The bird and the crested bird are found alike (both orders), the star is
// no look-alike of either, and the places of each pair lie at the crest:
// in the crested bird's table on the crest itself, in the plain bird's
// where the crest would rise.
TEST_F(DiscriminativePlacesTest, TwoDrawnLookAlikesDifferAtTheCrest)
{
  const amcr::DiscriminativePlaces places = build();
  const amcr::AlikePair* crested_bird = places.find(kCrested, kBird);
  const amcr::AlikePair* bird_crested = places.find(kBird, kCrested);
  ASSERT_NE(crested_bird, nullptr) << "the two birds are look-alikes";
  ASSERT_NE(bird_crested, nullptr);
  EXPECT_EQ(places.find(kStar, kBird), nullptr);
  EXPECT_EQ(places.find(kBird, kStar), nullptr);
  EXPECT_EQ(places.find(kCrested, kStar), nullptr);

  // The alignment maps the crested bird's tail and beak onto the plain bird's (same image px).
  for (const cv::Point2d& part : {cv::Point2d(15, 80), cv::Point2d(185, 95), amcr_test::kCrestBase})
    EXPECT_LT(distance(amcr::applyAffine(crested_bird->a_to_b, toTable((*memory)[kCrested], part)),
                       toTable((*memory)[kBird], part)),
              1.5)
        << "at image point " << part;

  // The crest: the triangle between its base and tip, in each table.
  const cv::Point2d crest_middle = 0.5 * (amcr_test::kCrestTip + amcr_test::kCrestBase);
  for (const amcr::AlikePair* pair : {crested_bird, bird_crested})
  {
    const amcr::Prototype& a = (*memory)[pair->a];
    ASSERT_FALSE(pair->places.empty()) << a.label();
    const cv::Point2d crest = toTable(a, crest_middle);
    // Half the crest's height plus a quarter of it: 25 table px of 160.
    const double near = 0.125 * std::max(a.width(), a.height());
    const amcr::DiscriminativePlace& best = pair->places.front();
    EXPECT_LT(distance({best.x, best.y}, crest), near) << a.label() << ": the best place lies at the crest";
    for (std::size_t k = 1; k < pair->places.size(); ++k)
    {
      EXPECT_LE(pair->places[k].divergence, pair->places[k - 1].divergence);
      EXPECT_GE(distance({pair->places[k].x, pair->places[k].y}, {best.x, best.y}),
                amcr::kPlaceSpacing * std::max(a.width(), a.height()) - 1e-6);
    }
    // Where the birds agree (the tail) their scans differ little.
    const cv::Point2d tail = toTable(a, {50, 88});
    EXPECT_LT(amcr::placeDivergence(a, (*memory)[pair->b], pair->a_to_b, observation, static_cast<int>(tail.x),
                                    static_cast<int>(tail.y)),
              0.25 * best.divergence)
        << a.label();
  }
}

TEST_F(DiscriminativePlacesTest, BytesRoundTripAndRefuseWhatDoesNotFit)
{
  const amcr::DiscriminativePlaces places = build();
  ASSERT_EQ(places.pairs().size(), 2u);
  const std::vector<std::uint8_t> bytes = places.toBytes();
  const amcr::DiscriminativePlaces back = amcr::DiscriminativePlaces::fromBytes(bytes.data(), bytes.size(), 3);
  EXPECT_EQ(back.toBytes(), bytes);

  EXPECT_THROW(amcr::DiscriminativePlaces::fromBytes(bytes.data(), bytes.size() - 1, 3), amcr::MemoryError);
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_THROW(amcr::DiscriminativePlaces::fromBytes(longer.data(), longer.size(), 3), amcr::MemoryError);
  // A memory of one prototype has no pair (0, 1).
  try
  {
    amcr::DiscriminativePlaces::fromBytes(bytes.data(), bytes.size(), 1);
    FAIL() << "a pair naming a prototype the memory lacks must be refused";
  }
  catch (const amcr::MemoryError& e)
  {
    EXPECT_NE(std::string(e.what()).find("not two of the memory's 1"), std::string::npos) << e.what();
  }
}

// The places are kept in the table cache: built and written once, read back
// the same; a damaged file is reported and compared again.
TEST_F(DiscriminativePlacesTest, KeptInTheTableCache)
{
  const amcr_test::TempDir dir;
  const amcr::TableCache cache(dir.path());
  const amcr::DiscriminativePlacesSettings settings;
  std::vector<std::string> warnings;
  const auto warn = [&warnings](const std::string& line) { warnings.push_back(line); };

  const auto built = amcr::loadDiscriminativePlaces(*memory, observation, settings, {}, &cache, warn);
  EXPECT_TRUE(warnings.empty());
  const std::uint64_t key = amcr::discriminativePlacesKey(*memory, observation, settings, {});
  std::vector<std::uint8_t> payload;
  const std::string name = amcr::discriminativePlacesCacheName(key);
  ASSERT_EQ(cache.readPayload(name, key, payload), "");
  EXPECT_EQ(payload, built->toBytes());
  const auto read = amcr::loadDiscriminativePlaces(*memory, observation, settings, {}, &cache, warn);
  EXPECT_EQ(read->toBytes(), built->toBytes());
  EXPECT_TRUE(warnings.empty());

  // Another observation model is another key.
  amcr::Params wider = params;
  wider.sigma_w = 2.0 * params.sigma_w;
  EXPECT_NE(amcr::discriminativePlacesKey(*memory, amcr::ObservationModel(wider), settings, {}), key);

  {
    std::fstream file(dir.file(name), std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(-3, std::ios::end);
    file.put('\x5a');
  }
  const auto again = amcr::loadDiscriminativePlaces(*memory, observation, settings, {}, &cache, warn);
  EXPECT_EQ(again->toBytes(), built->toBytes());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("refused"), std::string::npos) << warnings[0];
}
}  // namespace
