// Attention that discriminates (discriminative_attention.h): the competing
// clusters of a V-particle, the scans they predict from their tables alone,
// and the move chosen where those predictions differ.
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/discriminative_attention.h"
#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/observation_model.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/base/random.h"
#include "amcr/scan/ray_directions.h"
#include "scene_drawing.h"

namespace
{
// Two drawn prototypes with the same bounding box, so that their tables
// align pixel for pixel: a plain rectangle, and the same rectangle with a
// triangular notch cut into its right side (prototype-image px).
const std::vector<cv::Point2d> kPlain = {{30, 60}, {170, 60}, {170, 140}, {30, 140}};
const std::vector<cv::Point2d> kNotched = {{30, 60}, {170, 60}, {170, 80}, {140, 100}, {170, 120}, {170, 140}, {30, 140}};
constexpr int kPlainIndex = 0;
constexpr int kNotchedIndex = 1;

std::shared_ptr<const amcr::PrototypeMemory> plainAndNotched(const amcr::Params& params)
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("plain", amcr_test::drawSilhouette(kPlain), params);
  memory->add("notched", amcr_test::drawSilhouette(kNotched), params);
  return memory;
}

/// A hypothesis of `prototype` at table point `at`, anchored at image point
/// `anchor`, with image px = table px (identity linear part).
amcr::CompetingHypothesis hypothesis(int prototype, cv::Point2d at, cv::Point2f anchor, float share)
{
  amcr::CompetingHypothesis h;
  h.prototype = prototype;
  h.x = static_cast<float>(at.x);
  h.y = static_cast<float>(at.y);
  h.image_x = anchor.x;
  h.image_y = anchor.y;
  h.share = share;
  return h;
}

cv::Point2d toTable(const amcr::Prototype& p, cv::Point2d original) { return amcr::applyAffine(p.originalToTable(), original); }

/// `count` M-particles of `prototype` spread uniformly within +-`spread` table
/// px of `centre`, with log likelihood `log_likelihood` and a fitted affine
/// (or none), appended to `m`.
void addParticles(amcr::MParticleSet& m, amcr::Rng& rng, int count, int prototype, cv::Point2f centre, float spread,
                  float log_likelihood, bool with_affine = true)
{
  const std::size_t begin = m.size();
  m.resize(begin + static_cast<std::size_t>(count));
  for (std::size_t k = begin; k < m.size(); ++k)
  {
    m.prototype[k] = prototype;
    m.x[k] = centre.x + static_cast<float>(rng.uniform(-spread, spread));
    m.y[k] = centre.y + static_cast<float>(rng.uniform(-spread, spread));
    m.theta[k] = 0.f;
    m.log_likelihood[k] = log_likelihood;
    m.affine_valid[k] = with_affine ? amcr::kFittedAffine : amcr::kNoAffine;
    const float identity[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};
    for (int a = 0; a < 6; ++a)
      m.affine[a][k] = identity[a];
  }
}

TEST(CompetingHypotheses, FindsEachClusterWithItsShareMostLikelyFirst)
{
  amcr::MParticleSet m;
  amcr::Rng rng(3);
  addParticles(m, rng, 40, 2, {50, 50}, 2.f, -10.f);   // a cluster in prototype 2
  addParticles(m, rng, 30, 5, {80, 20}, 2.f, -8.f);    // a more likely one in prototype 5
  addParticles(m, rng, 20, 2, {90, 90}, 2.f, -12.f);   // another place of prototype 2
  addParticles(m, rng, 10, 7, {30, 30}, 2.f, -1.f, false);  // the most likely, but without an affine
  const amcr::MRange all{0, m.size()};
  m.log_likelihood[45] = -7.f;  // the best of prototype 5's cluster (index 40..69)

  const amcr::CompetingHypotheses h = amcr::competingHypotheses(m, all, 100.f, 200.f, 6.f, 0.05f);
  ASSERT_EQ(h.count, 3);
  EXPECT_EQ(h.hypothesis[0].prototype, 5);
  EXPECT_FLOAT_EQ(h.hypothesis[0].x, m.x[45]);
  EXPECT_NEAR(h.hypothesis[0].share, 0.30f, 1e-6);
  EXPECT_EQ(h.hypothesis[1].prototype, 2);
  EXPECT_NEAR(h.hypothesis[1].share, 0.40f, 1e-6);
  EXPECT_NEAR(h.hypothesis[1].x, 50.f, 2.f);
  EXPECT_EQ(h.hypothesis[2].prototype, 2);
  EXPECT_NEAR(h.hypothesis[2].share, 0.20f, 1e-6);
  EXPECT_NEAR(h.hypothesis[2].x, 90.f, 2.f);
  EXPECT_FLOAT_EQ(h.hypothesis[0].image_x, 100.f);
  EXPECT_FLOAT_EQ(h.hypothesis[0].image_y, 200.f);

  // A share below the minimum does not compete.
  const amcr::CompetingHypotheses large = amcr::competingHypotheses(m, all, 100.f, 200.f, 6.f, 0.25f);
  ASSERT_EQ(large.count, 2);
  EXPECT_EQ(large.hypothesis[0].prototype, 5);
  EXPECT_EQ(large.hypothesis[1].prototype, 2);
  // Only the V-particle's own range counts.
  const amcr::CompetingHypotheses first = amcr::competingHypotheses(m, {0, 40}, 0.f, 0.f, 6.f, 0.05f);
  ASSERT_EQ(first.count, 1);
  EXPECT_NEAR(first.hypothesis[0].share, 1.0f, 1e-6);
}

TEST(CompetingHypotheses, AffineMapsTheAnchorOntoTheParticle)
{
  amcr::CompetingHypothesis h = hypothesis(0, {40, 60}, {300, 200}, 0.5f);
  const float linear[4] = {0.5f, 0.1f, -0.2f, 0.8f};
  std::copy(linear, linear + 4, h.linear);
  amcr::Affine table_to_image;
  ASSERT_TRUE(amcr::hypothesisTableToImage(h, table_to_image));
  const cv::Point2d anchor = amcr::applyAffine(table_to_image, {40, 60});
  EXPECT_NEAR(anchor.x, 300.0, 1e-4);
  EXPECT_NEAR(anchor.y, 200.0, 1e-4);
  // One image px to the right is the first column of the linear part in the table.
  amcr::Affine image_to_table;
  ASSERT_TRUE(amcr::invertAffine(table_to_image, image_to_table));
  const cv::Point2d right = amcr::applyAffine(image_to_table, {301, 200});
  EXPECT_NEAR(right.x - 40.0, 0.5, 1e-5);  // float linear part
  EXPECT_NEAR(right.y - 60.0, -0.2, 1e-5);

  const float singular[4] = {1.f, 2.f, 2.f, 4.f};
  std::copy(singular, singular + 4, h.linear);
  EXPECT_FALSE(amcr::hypothesisTableToImage(h, table_to_image));
}

TEST(PredictedRays, ReadTheTableMappedBackToImagePixels)
{
  amcr::Params params;
  const auto memory = plainAndNotched(params);
  const amcr::Prototype& plain = (*memory)[kPlainIndex];
  const cv::Point2d at = toTable(plain, {60, 100});
  amcr::CompetingHypothesis h = hypothesis(kPlainIndex, at, {0, 0}, 1.f);
  const cv::Point pixel(static_cast<int>(std::lround(at.x)), static_cast<int>(std::lround(at.y)));

  amcr::RaySignature rays;
  ASSERT_TRUE(amcr::predictedRays(plain, h, 0.f, 0.f, 0.f, rays));
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    EXPECT_NEAR(rays.distance[k], plain.distance(pixel.x, pixel.y, k * amcr::kFeatureBinStep), 1e-4) << "ray " << k;

  // The image seen at half the table's scale: each image px is 2 table px,
  // so every distance halves.
  const float half[4] = {2.f, 0.f, 0.f, 2.f};
  std::copy(half, half + 4, h.linear);
  amcr::RaySignature halved;
  ASSERT_TRUE(amcr::predictedRays(plain, h, 0.f, 0.f, 0.f, halved));
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    EXPECT_NEAR(halved.distance[k], 0.5f * rays.distance[k], 1e-4) << "ray " << k;

  // A move that leaves the table predicts nothing.
  EXPECT_FALSE(amcr::predictedRays(plain, h, 1000.f, 0.f, 0.f, rays));
}

TEST(ScanDivergence, IsZeroForEqualScansAndGrowsWithTheDeviation)
{
  amcr::Params params;
  const amcr::ObservationModel observation(params);
  amcr::RaySignature a;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    a.distance[k] = 20.f + k;
  amcr::RaySignature near = a, far = a, none = a;
  near.distance[2] += 3.f;
  far.distance[2] += 30.f;
  none.distance[2] = 0.f;
  EXPECT_DOUBLE_EQ(amcr::scanDivergence(a, a, observation), 0.0);
  const double d_near = amcr::scanDivergence(a, near, observation);
  const double d_far = amcr::scanDivergence(a, far, observation);
  EXPECT_GT(d_near, 0.0);
  EXPECT_GT(d_far, d_near);
  EXPECT_NEAR(d_far, observation.logRay(0.0) - observation.logRay(30.0), 1e-3);
  // A ray with an edge against one without: eq. 6 gives p_invalid.
  EXPECT_NEAR(amcr::scanDivergence(a, none, observation),
              std::max(0.0, observation.logRay(0.0) - observation.logInvalid()), 1e-3);
}

// The move choice on a hand-made pair of clusters: the plain and the notched
// rectangle, both at the same place. From the V-particle's place no ray meets
// the notch, so its scan there cannot tell them apart; the chosen move is one
// from which a ray meets the notch, and no candidate tells them apart better.
TEST(DiscriminativeMoveChooser, PicksAMoveWhosePredictedScansDiffer)
{
  amcr::Params params;
  const auto memory = plainAndNotched(params);
  const amcr::ObservationModel observation(params);
  const amcr::Prototype& plain = (*memory)[kPlainIndex];
  const cv::Point2f v_place(200.f, 200.f);
  const cv::Point2d at = toTable(plain, {60, 123});  // below the notch's rows (80-120), left of it
  amcr::CompetingHypotheses h;
  h.count = 2;
  h.hypothesis[0] = hypothesis(kPlainIndex, at, v_place, 0.5f);
  h.hypothesis[1] = hypothesis(kNotchedIndex, at, v_place, 0.4f);

  amcr::VParticle v;
  v.x = v_place.x;
  v.y = v_place.y;
  v.theta = 0.f;  // v.rays all 0: no edge limits the moves

  amcr::RaySignature here_plain, here_notched;
  ASSERT_TRUE(amcr::predictedRays((*memory)[kPlainIndex], h.hypothesis[0], 0.f, 0.f, v.theta, here_plain));
  ASSERT_TRUE(amcr::predictedRays((*memory)[kNotchedIndex], h.hypothesis[1], 0.f, 0.f, v.theta, here_notched));
  ASSERT_LT(amcr::scanDivergence(here_plain, here_notched, observation), 0.01)
      << "the set-up: from the V-particle's place no ray may meet the notch";

  // Any gain is enough here: the test is about which move is chosen.
  const amcr::DiscriminativeMoveChooser chooser(params.v_step, 0.0);
  amcr::DiscriminativeMove move;
  ASSERT_TRUE(chooser.choose(v, h, *memory, observation, cv::Size(400, 400), nullptr, move));
  const double heading = v.theta + move.control.rotation;
  const float dx = static_cast<float>(move.control.translation * std::cos(heading));
  const float dy = static_cast<float>(move.control.translation * std::sin(heading));
  amcr::RaySignature moved_plain, moved_notched;
  ASSERT_TRUE(amcr::predictedRays((*memory)[kPlainIndex], h.hypothesis[0], dx, dy, static_cast<float>(heading),
                                  moved_plain));
  ASSERT_TRUE(amcr::predictedRays((*memory)[kNotchedIndex], h.hypothesis[1], dx, dy, static_cast<float>(heading),
                                  moved_notched));
  float largest = 0.f;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    largest = std::max(largest, std::abs(moved_plain.distance[k] - moved_notched.distance[k]));
  EXPECT_GT(largest, 5.f) << "the chosen move's scans should meet the notch in one hypothesis and not the other";
  EXPECT_LT(dy, 0.f) << "the notch's rows lie above the V-particle";
  EXPECT_GT(move.gain, 0.05);

  // No candidate tells them apart better (the candidates of the header: k * 45 deg, 1 or 2 steps).
  const double weight = 2.0 * 0.5 * 0.4 / (0.9 * 0.9);
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    for (double multiple : {1.0, 2.0})
    {
      const double a = k * M_PI / 4, length = multiple * params.v_step;
      amcr::RaySignature p, n;
      ASSERT_TRUE(amcr::predictedRays((*memory)[kPlainIndex], h.hypothesis[0], static_cast<float>(length * std::cos(a)),
                                      static_cast<float>(length * std::sin(a)), static_cast<float>(a), p));
      ASSERT_TRUE(amcr::predictedRays((*memory)[kNotchedIndex], h.hypothesis[1],
                                      static_cast<float>(length * std::cos(a)), static_cast<float>(length * std::sin(a)),
                                      static_cast<float>(a), n));
      EXPECT_LE(weight * amcr::scanDivergence(p, n, observation), move.gain + 1e-9);
    }

  // Alone, or with both clusters' scans equal everywhere, there is nothing
  // to decide (the default least gain).
  const amcr::DiscriminativeMoveChooser with_threshold(params.v_step, params.discriminative_min_gain);
  amcr::CompetingHypotheses one = h;
  one.count = 1;
  EXPECT_FALSE(with_threshold.choose(v, one, *memory, observation, cv::Size(400, 400), nullptr, move));
  amcr::CompetingHypotheses same = h;
  same.hypothesis[1].prototype = kPlainIndex;
  EXPECT_FALSE(with_threshold.choose(v, same, *memory, observation, cv::Size(400, 400), nullptr, move));
}

// A move never takes the V-particle past the edge its last scan met, nor out of the image.
TEST(DiscriminativeMoveChooser, StaysBeforeTheEdgesOfItsLastScan)
{
  amcr::Params params;
  const auto memory = plainAndNotched(params);
  const amcr::ObservationModel observation(params);
  const cv::Point2d at = toTable((*memory)[kPlainIndex], {60, 128});
  amcr::VParticle v;
  v.x = 200.f;
  v.y = 200.f;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    v.rays.distance[k] = 6.f;  // an edge 6 px away on every ray: only one step (4 px) fits
  amcr::CompetingHypotheses h;
  h.count = 2;
  h.hypothesis[0] = hypothesis(kPlainIndex, at, {v.x, v.y}, 0.5f);
  h.hypothesis[1] = hypothesis(kNotchedIndex, at, {v.x, v.y}, 0.5f);
  const amcr::DiscriminativeMoveChooser chooser(params.v_step, 0.0);
  amcr::DiscriminativeMove move;
  ASSERT_TRUE(chooser.choose(v, h, *memory, observation, cv::Size(400, 400), nullptr, move));
  EXPECT_LE(move.control.translation, 6.0 - 1.5);
  // At the image's corner, moves that leave the image are not candidates.
  v.x = 2.f;
  v.y = 2.f;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
    v.rays.distance[k] = 0.f;
  ASSERT_TRUE(chooser.choose(v, h, *memory, observation, cv::Size(400, 400), nullptr, move));
  const double heading = v.theta + move.control.rotation;
  EXPECT_GE(v.x + move.control.translation * std::cos(heading), 1.0);
  EXPECT_GE(v.y + move.control.translation * std::sin(heading), 1.0);
}

// With precomputed places, a V-particle deciding between the bird and the
// crested bird from the tail heads for the crest (a lookup, however far it
// lies); once within two steps of it, the candidate moves are scored again.
TEST(DiscriminativeMoveChooser, HeadsForTheNearestPrecomputedPlace)
{
  amcr::Params params;
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("bird", amcr_test::drawSilhouette(amcr_test::drawnBird(false)), params);
  memory->add("crested", amcr_test::drawSilhouette(amcr_test::drawnBird(true)), params);
  const amcr::ObservationModel observation(params);
  const amcr::DiscriminativePlaces places =
      amcr::DiscriminativePlaces::build(*memory, observation, amcr::DiscriminativePlacesSettings());
  const amcr::AlikePair* pair = places.find(1, 0);
  ASSERT_NE(pair, nullptr);
  ASSERT_FALSE(pair->places.empty());

  const amcr::Prototype& crested = (*memory)[1];
  const cv::Point2f v_place(200.f, 200.f);
  const auto deciding = [&](cv::Point2d original) {
    amcr::CompetingHypotheses h;
    h.count = 2;
    h.hypothesis[0] = hypothesis(1, toTable(crested, original), v_place, 0.6f);
    h.hypothesis[1] = hypothesis(0, toTable((*memory)[0], original), v_place, 0.3f);
    return h;
  };
  amcr::VParticle v;
  v.x = v_place.x;
  v.y = v_place.y;
  v.theta = 0.3f;
  const amcr::DiscriminativeMoveChooser chooser(params.v_step, params.discriminative_min_gain);
  amcr::DiscriminativeMove move;

  // From inside the body near the tail, the nearest place is beyond two steps.
  amcr::CompetingHypotheses h = deciding({60, 100});
  ASSERT_TRUE(chooser.choose(v, h, *memory, observation, cv::Size(400, 400), &places, move));
  EXPECT_TRUE(move.to_place);
  // The place nearest the V-particle's table point, in the image (table px = image px here).
  double nearest = 1e9;
  cv::Point2d target;
  float target_divergence = 0.f;
  for (const amcr::DiscriminativePlace& p : pair->places)
  {
    const double d = std::hypot(p.x - h.hypothesis[0].x, p.y - h.hypothesis[0].y);
    if (d < nearest)
    {
      nearest = d;
      target = cv::Point2d(v_place) + cv::Point2d(p.x - h.hypothesis[0].x, p.y - h.hypothesis[0].y);
      target_divergence = p.divergence;
    }
  }
  ASSERT_GT(nearest, 2.0 * params.v_step);
  const double heading = v.theta + move.control.rotation;
  const cv::Point2d moved(v.x + move.control.translation * std::cos(heading),
                          v.y + move.control.translation * std::sin(heading));
  EXPECT_LT(std::hypot(target.x - moved.x, target.y - moved.y),
            nearest - 0.5 * move.control.translation)
      << "the step goes toward the place (along the feature ray nearest its direction)";
  EXPECT_GT(move.control.translation, 0.0);
  EXPECT_FLOAT_EQ(static_cast<float>(move.gain), target_divergence) << "the gain is the place's divergence";

  // Without the places, the same V-particle scores the candidate moves
  // (any gain is enough here: the test is about which kind of move it is).
  const amcr::DiscriminativeMoveChooser scoring(params.v_step, 0.0);
  amcr::DiscriminativeMove scored;
  ASSERT_TRUE(scoring.choose(v, h, *memory, observation, cv::Size(400, 400), nullptr, scored));
  EXPECT_FALSE(scored.to_place);

  // At the place itself the candidate moves are scored.
  const amcr::DiscriminativePlace& best = pair->places.front();
  h.hypothesis[0].x = best.x;
  h.hypothesis[0].y = best.y;
  h.hypothesis[1].x = static_cast<float>(amcr::applyAffine(pair->a_to_b, {best.x, best.y}).x);
  h.hypothesis[1].y = static_cast<float>(amcr::applyAffine(pair->a_to_b, {best.x, best.y}).y);
  amcr::DiscriminativeMove near;
  ASSERT_TRUE(scoring.choose(v, h, *memory, observation, cv::Size(400, 400), &places, near));
  EXPECT_FALSE(near.to_place);
}
}  // namespace
