// Verification against simpler explanations (generic_rivals.h): the parts of
// a prototype's outline that tell it from an ellipse, its convex hull, its
// rectangle or a pair of lines, checked on drawn images. An apple on a disc
// verifies on most of its outline (its body) but not on its stem, which is
// what tells it from the disc; a target with a hole on a plain rectangle
// fails on its hole.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/homography.h"
#include "amcr/extraction/generic_rivals.h"
#include "amcr/extraction/homography_fit.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/rival_cache.h"
#include "amcr/memory/prototype_memory.h"
#include "scene_drawing.h"

namespace
{
constexpr double kTolerance = 1.5;  // px, the score's tolerance at these sizes
constexpr double kApart = 3.0;      // px: two tolerances, as the extraction uses
constexpr int kMinPoints = 6;

std::vector<cv::Point2d> circle(cv::Point2d centre, double radius)
{
  return amcr_test::wavyOval(centre, radius, radius, 0.0);
}

// A printed target: a rectangle 160 x 110 px with a round hole of radius 25
// (with `hole`), white on black as a prototype.
cv::Mat targetImage(bool hole)
{
  cv::Mat image(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
  amcr_test::fillPolygon(image, {{20, 45}, {180, 45}, {180, 155}, {20, 155}}, 255);
  if (hole)
    amcr_test::fillPolygon(image, circle({120, 100}, 25), 0);
  return image;
}

// The prototype-image -> scene affine of the tests: turned, scaled 0.6 (a
// 120 px object), in the middle of a 640 x 480 scene.
amcr::Affine toScene()
{
  return amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.5, 0.6, 0.6, 0.0);
}

// A scene: a shape (a prototype image, white = shape) printed dark on light
// paper under toScene(), with a little noise.
cv::Mat sceneOf(const cv::Mat& shape)
{
  cv::Mat scene(480, 640, CV_8UC1, cv::Scalar(200));
  cv::Mat warped;
  cv::warpAffine(shape, warped, cv::Mat(toScene()), scene.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  scene -= warped * (160.0 / 255.0);
  return amcr_test::addNoise(scene, 3.0, 11);
}

struct Check
{
  amcr::RivalVerdict verdict;
  double score = 0.0;  // the whole outline's score at the same tolerance
};

// A prototype checked against its rivals where `scene` shows something
// under toScene().
Check check(const std::string& label, const cv::Mat& prototype_image, const cv::Mat& scene)
{
  amcr::PrototypeMemory memory;
  const amcr::Params params;
  memory.add(label, prototype_image, params);
  const amcr::Prototype& p = memory[0];
  const cv::Mat smoothed = amcr::prepareScanImage(scene, params.blur_sigma);
  const amcr::RadialScanner scanner(smoothed, params.edge_threshold, params.max_ray_length);
  const amcr::Affine table_to_image = amcr::composeAffine(p.tableToOriginal(), toScene());
  const amcr::Homography h = amcr::liftAffine(table_to_image);
  Check out;
  out.verdict = amcr::verifyAgainstRivals(scanner, amcr::mapOutline(p, h), amcr::genericRivals(p), h, kTolerance,
                                          kApart, kMinPoints);
  out.score = amcr::outlineSupport(p, scanner, table_to_image, kTolerance);
  return out;
}

// The rivals depend on the prototype alone: the cache fits each once, gives
// what genericRivals gives, and starts over for another memory.
TEST(RivalCache, FitsEachPrototypeOnceAndStartsOverForAnotherMemory)
{
  const auto memory = amcr_test::drawnMemory({amcr_test::ShapeId::kArrow, amcr_test::ShapeId::kStar});
  amcr::RivalCache cache;
  EXPECT_FALSE(cache.has(0));
  cache.fit(*memory, {1, 1, 7, -1}, 2);  // twice, out of range: fitted once, the rest ignored
  EXPECT_FALSE(cache.has(0));
  ASSERT_TRUE(cache.has(1));
  EXPECT_EQ(cache.fitted(), 1u);
  const std::vector<amcr::GenericRival> direct = amcr::genericRivals((*memory)[1]);
  ASSERT_EQ(cache.rivals(1).size(), direct.size());
  ASSERT_FALSE(direct.empty());
  for (std::size_t k = 0; k < direct.size(); ++k)
  {
    EXPECT_EQ(cache.rivals(1)[k].kind, direct[k].kind);
    EXPECT_EQ(cache.rivals(1)[k].points, direct[k].points);
  }
  cache.fit(*memory, {0}, 1);
  EXPECT_EQ(cache.fitted(), 2u);
  const auto larger = amcr_test::drawnMemory(
      {amcr_test::ShapeId::kArrow, amcr_test::ShapeId::kStar, amcr_test::ShapeId::kFlag});
  cache.fit(*larger, {2}, 1);  // another memory's size: what was fitted for the other is gone
  EXPECT_FALSE(cache.has(0));
  EXPECT_TRUE(cache.has(2));
  cache.clear();
  EXPECT_EQ(cache.fitted(), 0u);
  EXPECT_TRUE(cache.rivals(2).empty());
}
}  // namespace

TEST(GenericRivals, AnAppleHasFourRivalsAndItsEllipseIsItsBody)
{
  amcr::PrototypeMemory memory;
  memory.add("apple", amcr_test::drawApple(true), amcr::Params());
  const amcr::Prototype& p = memory[0];
  const std::vector<amcr::GenericRival> rivals = amcr::genericRivals(p);
  ASSERT_EQ(rivals.size(), 4u);
  EXPECT_EQ(rivals[0].kind, amcr::GenericRival::Kind::kEllipse);
  EXPECT_EQ(rivals[3].kind, amcr::GenericRival::Kind::kLinePair);
  EXPECT_EQ(rivals[3].points.size(), 4u);
  // The robust ellipse follows the body, not the stem: its centre and radius
  // are the body's within 2 % of the body's radius (table px).
  const amcr::Affine to_table = p.originalToTable();
  const cv::Point2d centre = amcr::applyAffine(to_table, amcr_test::kAppleCentre);
  const double radius = amcr_test::kAppleRadius * std::hypot(to_table(0, 0), to_table(1, 0));
  for (const cv::Point2d& q : rivals[0].points)
    EXPECT_NEAR(std::hypot(q.x - centre.x, q.y - centre.y), radius, 0.02 * radius);
}

TEST(GenericRivals, AnAppleOnADiscFailsOnItsStemWhileItsScorePasses)
{
  const Check on_disc = check("apple", amcr_test::drawApple(true), sceneOf(amcr_test::drawApple(false)));
  const Check on_apple = check("apple", amcr_test::drawApple(true), sceneOf(amcr_test::drawApple(true)));
  // The knife the score alone has: the disc explains the apple's body.
  EXPECT_GE(on_disc.score, 0.75) << "the disc does not pass the score: the scene does not test the rivals";
  ASSERT_TRUE(on_disc.verdict.tested);
  EXPECT_LE(on_disc.verdict.support, 0.2) << "the stem was found on a disc (rival "
                                          << amcr::rivalName(on_disc.verdict.rival) << ")";
  ASSERT_TRUE(on_apple.verdict.tested);
  EXPECT_GE(on_apple.verdict.support, 0.9) << "the apple's own stem was not found (rival "
                                            << amcr::rivalName(on_apple.verdict.rival) << ")";
  EXPECT_GE(on_apple.score, 0.9);
}

TEST(GenericRivals, ATargetWithAHoleOnAPlainRectangleFailsOnItsHole)
{
  const Check on_plain = check("target", targetImage(true), sceneOf(targetImage(false)));
  const Check on_target = check("target", targetImage(true), sceneOf(targetImage(true)));
  ASSERT_TRUE(on_plain.verdict.tested);
  EXPECT_LE(on_plain.verdict.support, 0.2);
  EXPECT_GE(on_target.verdict.support, 0.9);
}

TEST(GenericRivals, AShapeThatIsItsRivalIsNotHeldAgainstIt)
{
  // A disc is its own ellipse and hull: only the rectangle and the pair of
  // lines differ from it, and the disc's image shows those parts.
  cv::Mat disc(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
  amcr_test::fillPolygon(disc, circle(amcr_test::prototypeCentre(), 70), 255);
  const Check on_disc = check("disc", disc, sceneOf(disc));
  EXPECT_GE(on_disc.verdict.support, 0.9);
  EXPECT_NE(on_disc.verdict.rival, amcr::GenericRival::Kind::kEllipse);
}

TEST(GenericRivals, NoOutlineNoRivalNoVerdict)
{
  cv::Mat blank(50, 50, CV_8UC1, cv::Scalar(0));
  const amcr::RadialScanner scanner(blank, 10.0, 100.0);
  const amcr::RivalVerdict verdict = amcr::verifyAgainstRivals(scanner, {}, {}, amcr::liftAffine(amcr::identityAffine()),
                                                               kTolerance, kApart, kMinPoints);
  EXPECT_FALSE(verdict.tested);
  EXPECT_EQ(verdict.support, 1.0);
}
