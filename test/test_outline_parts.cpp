// The inner parts of an outline fitted on their own (outline_parts.h): a
// printed target whose prototype has its hole drawn a few percent off (place
// and size) still scores on its hole once the part may move, and a part
// never moves farther than it may.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/homography_fit.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/outline_parts.h"
#include "amcr/memory/prototype_memory.h"
#include "scene_drawing.h"

namespace
{
constexpr double kTolerance = 1.0;  // px: the score's tolerance at about 120 px

// A target 160 x 110 px with a round hole of radius `radius` at `hole`,
// white on black as a prototype.
cv::Mat target(cv::Point2d hole, double radius)
{
  cv::Mat image(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
  amcr_test::fillPolygon(image, {{20, 45}, {180, 45}, {180, 155}, {20, 155}}, 255);
  amcr_test::fillPolygon(image, amcr_test::wavyOval(hole, radius, radius, 0.0), 0);
  return image;
}

const cv::Point2d kHole(120, 100);
constexpr double kRadius = 25;

amcr::Affine toScene() { return amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.3, 0.75, 0.75, 0.0); }

cv::Mat sceneOf(const cv::Mat& shape)
{
  cv::Mat scene(480, 640, CV_8UC1, cv::Scalar(200));
  cv::Mat warped;
  cv::warpAffine(shape, warped, cv::Mat(toScene()), scene.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  scene -= warped * (160.0 / 255.0);
  return amcr_test::addNoise(scene, 3.0, 7);
}

struct Fixture
{
  amcr::PrototypeMemory memory;
  cv::Mat smoothed;
  std::unique_ptr<amcr::RadialScanner> scanner;
  amcr::Affine table_to_image;

  // The prototype drawn with its hole `error` of the target's width off in
  // place (along x) and `error` smaller; the scene shows the true target.
  explicit Fixture(double error)
  {
    const amcr::Params params;
    memory.add("target", target(kHole + cv::Point2d(error * 160, 0), kRadius * (1.0 - error)), params);
    smoothed = amcr::prepareScanImage(sceneOf(target(kHole, kRadius)), params.blur_sigma);
    scanner = std::make_unique<amcr::RadialScanner>(smoothed, params.edge_threshold, params.max_ray_length);
    table_to_image = amcr::composeAffine(memory[0].tableToOriginal(), toScene());
  }
};
}  // namespace

TEST(OutlineParts, ATargetHasTwoPartsTheOuterTheLongest)
{
  amcr::PrototypeMemory memory;
  memory.add("target", target(kHole, kRadius), amcr::Params());
  const std::vector<amcr::MappedPoint> mapped = amcr::mapOutline(memory[0], amcr::identityAffine());
  const auto parts = amcr::outlineParts(mapped);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts.front().first, 0u);
  EXPECT_EQ(parts.back().second, mapped.size());
  EXPECT_GT(std::max(parts[0].second - parts[0].first, parts[1].second - parts[1].first),
            std::min(parts[0].second - parts[0].first, parts[1].second - parts[1].first));
}

TEST(OutlineParts, AHoleDrawnOffScoresOnceItMayMove)
{
  for (double error : {0.03, 0.05})
  {
    Fixture f(error);
    const amcr::Prototype& p = f.memory[0];
    const double fixed = amcr::outlineSupport(p, *f.scanner, f.table_to_image, kTolerance, 0.0);
    const double moving = amcr::outlineSupport(p, *f.scanner, f.table_to_image, kTolerance, 0.05);
    EXPECT_LT(fixed, 0.85) << "error " << error << ": the hole drawn off still scores: the case tests nothing";
    EXPECT_GE(moving, 0.95) << "error " << error << ": the hole did not find its edges";
  }
}

TEST(OutlineParts, APartMovesNoFartherThanItMay)
{
  Fixture f(0.03);  // the hole is 4.8 prototype px off, 3.6 px in the scene
  const std::vector<amcr::MappedPoint> mapped = amcr::mapOutline(f.memory[0], f.table_to_image);
  const double limit = 3.0;  // px: its edges are within reach, its place beyond
  std::vector<amcr::MappedPoint> moved = mapped;
  amcr::fitPartsOnEdges(*f.scanner, moved, limit, kTolerance);
  ASSERT_EQ(moved.size(), mapped.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < mapped.size(); ++i)
    largest = std::max(largest, std::hypot(moved[i].image.x - mapped[i].image.x, moved[i].image.y - mapped[i].image.y));
  EXPECT_GT(largest, 0.5 * limit) << "the hole did not move towards its edges";
  EXPECT_LE(largest, limit + 1e-6);
  // The outer part never moves.
  const auto parts = amcr::outlineParts(mapped);
  const auto outer = std::max_element(parts.begin(), parts.end(), [](const auto& a, const auto& b) {
    return a.second - a.first < b.second - b.first;
  });
  for (std::size_t i = outer->first; i < outer->second; ++i)
    EXPECT_EQ(moved[i].image, mapped[i].image);
  EXPECT_EQ(amcr::partShiftLimit(mapped, 0.0), 0.0);
}
