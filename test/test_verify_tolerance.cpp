// The score's tolerance relative to the object's size (verifyTolerance,
// include/amcr/extraction/outline_fit.h): its arithmetic, and what it is for. A drawn
// oval prototype is shown twice at 96 px long: once exactly, once as a
// look-alike whose outline waves 1.8 px about the oval's. With the fixed 2 px
// tolerance both score above the decision threshold; with the tolerance
// relative to the size (1 px at this size) the exact oval still does and the
// look-alike does not.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/outline_fit.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"
#include "scene_drawing.h"

namespace
{
constexpr double kDecisionThreshold = 0.75;  // the default decision_threshold
constexpr double kRelative = 0.008;          // the default verify_relative_tolerance
constexpr double kFixed = 2.0;               // the default verify_tolerance, px

struct OvalScene
{
  std::shared_ptr<amcr::PrototypeMemory> memory = std::make_shared<amcr::PrototypeMemory>();
  cv::Mat image;
  amcr::Affine exact;       // prototype px -> image px of the exact oval
  amcr::Affine look_alike;  // the same for the wavy one
};

/// The prototype: an 160 x 100 px oval, light on dark. The image: the
/// exact oval and the look-alike, dark on light, at 0.6 of the prototype's
/// size (96 px long), with a little noise.
OvalScene ovalScene()
{
  OvalScene scene;
  const cv::Point2d centre = amcr_test::prototypeCentre();
  cv::Mat prototype(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
  amcr_test::fillPolygon(prototype, amcr_test::wavyOval(centre, 80, 50, 0.0), 255);
  scene.memory->add("oval", prototype, amcr::Params());

  const double scale = 0.6;
  scene.exact = amcr_test::makeAffine(centre, {160, 200}, 0.3, scale, scale, 0.0);
  scene.look_alike = amcr_test::makeAffine(centre, {440, 260}, 0.3, scale, scale, 0.0);
  cv::Mat image(480, 640, CV_8UC1, cv::Scalar(200));
  amcr_test::fillPolygon(image, amcr_test::transformPoints(scene.exact, amcr_test::wavyOval(centre, 80, 50, 0.0)), 40);
  // 3 px in prototype px: 1.8 px in the image.
  amcr_test::fillPolygon(image, amcr_test::transformPoints(scene.look_alike, amcr_test::wavyOval(centre, 80, 50, 3.0)), 40);
  scene.image = amcr_test::addNoise(image, 3.0, 7);
  return scene;
}

/// The score of the oval prototype at `original_to_image` with the
/// tolerance the object's size gives under `relative`.
double score(const OvalScene& scene, const amcr::Affine& original_to_image, double relative)
{
  const amcr::Params params;
  const amcr::Prototype& prototype = (*scene.memory)[0];
  const cv::Mat scan = amcr::prepareScanImage(scene.image, params.blur_sigma);
  const amcr::RadialScanner scanner(scan, params.edge_threshold, params.max_ray_length);
  const amcr::Affine table_to_image = amcr::composeAffine(prototype.tableToOriginal(), original_to_image);
  std::vector<cv::Point2d> outline;
  for (const auto& o : prototype.outline())
    outline.push_back(amcr::applyAffine(table_to_image, cv::Point2d(o.position)));
  const double tolerance = amcr::verifyTolerance(amcr::outlineSize(outline), kFixed, relative);
  return amcr::outlineSupport(prototype, scanner, table_to_image, tolerance);
}
}  // namespace

TEST(VerifyTolerance, IsAShareOfTheSizeBetweenOnePixelAndTheFixedTolerance)
{
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(250.0, 2.0, 0.008), 2.0);
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(187.5, 2.0, 0.008), 1.5);
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(90.0, 2.0, 0.008), 1.0) << "never below 1 px";
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(1000.0, 2.0, 0.008), 2.0) << "never above the fixed tolerance";
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(1000.0, 0.5, 0.008), 0.5) << "a fixed tolerance below 1 px stays";
}

TEST(VerifyTolerance, ZeroOrNoShareKeepsTheFixedTolerance)
{
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(90.0, 2.0, 0.0), 2.0);
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(90.0, 3.0, std::numeric_limits<double>::quiet_NaN()), 3.0);
  EXPECT_DOUBLE_EQ(amcr::verifyTolerance(0.0, 2.0, 0.008), 1.0);
}

TEST(VerifyTolerance, ASmallLookAlikeFailsWhereTheShapeItselfPasses)
{
  const OvalScene scene = ovalScene();
  // The fixed tolerance cannot tell them apart.
  EXPECT_GE(score(scene, scene.exact, 0.0), 0.95);
  EXPECT_GE(score(scene, scene.look_alike, 0.0), kDecisionThreshold) << "the look-alike is within 2 px all round";
  // Relative to their size (96 px long: 1 px), only the shape itself passes.
  EXPECT_GE(score(scene, scene.exact, kRelative), 0.95);
  EXPECT_LT(score(scene, scene.look_alike, kRelative), 0.6);
}
