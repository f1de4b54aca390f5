// cutShape: a drawn shape under a known affine over clutter is cut from a
// region around it (rectangle or polygon, clean or noisy, grey or colour)
// close to the truth and builds a prototype; a part with inner edges is cut
// as a grey template too; bad regions and images give their reasons instead
// of a shape.
#include <cmath>
#include <iostream>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/memory/region_shape.h"
#include "scene_drawing.h"
#include "template_drawing.h"

namespace
{
using amcr_test::ShapeId;

/// Least intersection over union of a cut silhouette and the true shape.
constexpr double kMinIoU = 0.9;
/// Largest relative difference of the cut shape's area from the truth's.
constexpr double kAreaTolerance = 0.05;
/// Clutter-free px between the true shape's bounding box and the region
/// (the scene's distractors keep 25 px away).
constexpr double kRegionMargin = 12.0;

struct DrawnScene
{
  cv::Mat image;
  std::vector<cv::Point2d> truth;  ///< the shape's outline in the image, px
};

/// One shape near the centre of a 640 x 480 scene over distractor shapes (no
/// lines: RegionShape.ALineAcrossTheShapeIsCutOff draws its own).
DrawnScene drawScene(ShapeId id, double rotation, double scale)
{
  amcr_test::Scene scene;
  amcr_test::Placement placement;
  placement.shape = id;
  placement.prototype_to_image =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), {320.0, 240.0}, rotation, scale, 0.9 * scale, 0.15);
  scene.objects.push_back(placement);
  scene.clutter.lines = 0;
  scene.clutter.seed = 7 + static_cast<int>(id);
  DrawnScene drawn;
  drawn.image = amcr_test::renderClean(scene);
  drawn.truth = amcr_test::transformPoints(placement.prototype_to_image, amcr_test::shapePolygon(id));
  return drawn;
}

cv::Rect2d truthBox(const std::vector<cv::Point2d>& truth)
{
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  for (const cv::Point2d& p : truth)
  {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

std::vector<cv::Point2f> regionAround(const std::vector<cv::Point2d>& truth)
{
  const cv::Rect2d b = truthBox(truth);
  return amcr::rectangleRegion(b.x - kRegionMargin, b.y - kRegionMargin, b.width + 2 * kRegionMargin,
                               b.height + 2 * kRegionMargin);
}

struct Comparison
{
  double iou = 0.0;
  double area_ratio = 0.0;  ///< cut area / true area
  bool truth_inside = false;
};

/// The cut silhouette against the true shape, filled hard-edged, in the same crop.
Comparison compare(const amcr::CutShape& cut, const std::vector<cv::Point2d>& truth, const cv::Size& image_size)
{
  Comparison c;
  cv::Mat truth_mask = cv::Mat::zeros(image_size, CV_8UC1);
  amcr_test::fillPolygon(truth_mask, truth, 255.0, false);
  const cv::Rect inside = cut.bounds & cv::Rect(cv::Point(), image_size);
  if (inside != cut.bounds)
    return c;
  const cv::Mat truth_crop = truth_mask(cut.bounds);
  c.truth_inside = cv::countNonZero(truth_crop) == cv::countNonZero(truth_mask);
  const double both = cv::countNonZero(truth_crop & cut.silhouette);
  const double either = cv::countNonZero(truth_crop | cut.silhouette);
  c.iou = either > 0 ? both / either : 0.0;
  c.area_ratio = static_cast<double>(cv::countNonZero(cut.silhouette)) / cv::countNonZero(truth_crop);
  return c;
}

/// Expects `cut` to be the true shape and to make a prototype.
void expectShape(const amcr::CutShape& cut, const std::vector<cv::Point2d>& truth, const cv::Size& image_size,
                 const std::string& what)
{
  ASSERT_TRUE(cut.ok()) << what << ": " << cut.why;
  ASSERT_EQ(cut.silhouette.type(), CV_8UC1) << what;
  ASSERT_EQ(cut.silhouette.size(), cut.bounds.size()) << what;
  EXPECT_TRUE(cut.grey_template.empty()) << what << ": a plain shape has no inner edges";
  const Comparison c = compare(cut, truth, image_size);
  std::cout << "[ cut      ] " << what << ": IoU " << c.iou << ", area ratio " << c.area_ratio << "\n";
  EXPECT_TRUE(c.truth_inside) << what;
  EXPECT_GE(c.iou, kMinIoU) << what;
  EXPECT_NEAR(c.area_ratio, 1.0, kAreaTolerance) << what;
  const amcr::Params params;
  EXPECT_NO_THROW(
      amcr::Prototype(what, cut.silhouette, params.prototype_size, params.edge_threshold, params.blur_sigma))
      << what;
}

class CutEachShape : public ::testing::TestWithParam<ShapeId>
{};

TEST_P(CutEachShape, RectangleAroundTheShapeGivesItsSilhouette)
{
  const ShapeId id = GetParam();
  const double rotation = 0.4 + 1.1 * static_cast<int>(id);
  const DrawnScene scene = drawScene(id, rotation, 0.8);
  const amcr::CutShape cut = amcr::cutShape(scene.image, regionAround(scene.truth), amcr::Params());
  expectShape(cut, scene.truth, scene.image.size(), amcr_test::shapeName(id) + " in a rectangle");
}

TEST_P(CutEachShape, NoisyImage)
{
  const ShapeId id = GetParam();
  const DrawnScene scene = drawScene(id, -0.7 + 0.9 * static_cast<int>(id), 0.6);
  const cv::Mat noisy = amcr_test::addNoise(scene.image, 6.0, 11);
  const amcr::CutShape cut = amcr::cutShape(noisy, regionAround(scene.truth), amcr::Params());
  expectShape(cut, scene.truth, scene.image.size(), amcr_test::shapeName(id) + " with noise");
}

INSTANTIATE_TEST_SUITE_P(RegionShape, CutEachShape, ::testing::ValuesIn(amcr_test::allShapes()),
                         [](const ::testing::TestParamInfo<ShapeId>& info) {
                           return amcr_test::shapeName(info.param);
                         });

TEST(RegionShape, PolygonRegion)
{
  const DrawnScene scene = drawScene(ShapeId::kStar, 2.0, 0.7);
  // The rectangle around the shape with its corners cut off: an octagon.
  const cv::Rect2d b = truthBox(scene.truth);
  const double m = 20.0, cut_off = 8.0;
  const double x0 = b.x - m, y0 = b.y - m, x1 = b.x + b.width + m, y1 = b.y + b.height + m;
  const std::vector<cv::Point2f> octagon = {{float(x0 + cut_off), float(y0)}, {float(x1 - cut_off), float(y0)},
                                            {float(x1), float(y0 + cut_off)}, {float(x1), float(y1 - cut_off)},
                                            {float(x1 - cut_off), float(y1)}, {float(x0 + cut_off), float(y1)},
                                            {float(x0), float(y1 - cut_off)}, {float(x0), float(y0 + cut_off)}};
  const amcr::CutShape cut = amcr::cutShape(scene.image, octagon, amcr::Params());
  expectShape(cut, scene.truth, scene.image.size(), "star in an octagon");
}

TEST(RegionShape, ColourImage)
{
  const DrawnScene scene = drawScene(ShapeId::kArrow, 0.3, 0.7);
  cv::Mat colour;
  cv::cvtColor(scene.image, colour, cv::COLOR_GRAY2BGR);
  const amcr::CutShape cut = amcr::cutShape(colour, regionAround(scene.truth), amcr::Params());
  expectShape(cut, scene.truth, scene.image.size(), "arrow in colour");
}

TEST(RegionShape, TheLargestClosedOutlineClearOfTheBorderIsTheShape)
{
  cv::Mat image(200, 300, CV_8UC1, cv::Scalar(190));
  cv::circle(image, {80, 100}, 20, cv::Scalar(40), cv::FILLED);                   // small
  cv::rectangle(image, cv::Rect(140, 50, 90, 100), cv::Scalar(40), cv::FILLED);   // large
  cv::rectangle(image, cv::Rect(240, 20, 100, 160), cv::Scalar(40), cv::FILLED);  // larger, cut by the border
  const amcr::CutShape cut = amcr::cutShape(image, amcr::rectangleRegion(20, 10, 260, 180), amcr::Params());
  ASSERT_TRUE(cut.ok()) << cut.why;
  const cv::Rect expected(140 - amcr::kSilhouetteMargin, 50 - amcr::kSilhouetteMargin, 90 + 2 * amcr::kSilhouetteMargin,
                          100 + 2 * amcr::kSilhouetteMargin);
  EXPECT_LE(std::abs(cut.bounds.x - expected.x), 1);
  EXPECT_LE(std::abs(cut.bounds.y - expected.y), 1);
  EXPECT_LE(std::abs(cut.bounds.width - expected.width), 2);
  EXPECT_LE(std::abs(cut.bounds.height - expected.height), 2);
  EXPECT_NEAR(cv::countNonZero(cut.silhouette), 90 * 100, 0.05 * 90 * 100);
}

/// The point of the shape farthest inside it.
cv::Point2d deepestPoint(const std::vector<cv::Point2d>& truth, const cv::Size& size)
{
  cv::Mat mask = cv::Mat::zeros(size, CV_8UC1), distance;
  amcr_test::fillPolygon(mask, truth, 255.0, false);
  cv::distanceTransform(mask, distance, cv::DIST_L2, 3);
  cv::Point deepest;
  cv::minMaxLoc(distance, nullptr, nullptr, nullptr, &deepest);
  return deepest;
}

// A line (a cable, a table edge) across the shape, through its thickest
// part, and the whole region joins the outline to the region's border: the
// line is cut off and the shape is still cut close to the truth (the stubs
// of the line at the outline, a few px long, are left). Before, no outline
// stayed clear of the border and the cut failed ("no closed outline").
TEST(RegionShape, ALineAcrossTheShapeIsCutOff)
{
  struct Line
  {
    double grey;     // the line's grey level (background 190 or so, shapes darker)
    int width;       // px
    double angle;    // rad, through the shape's centre
  };
  for (ShapeId id : {ShapeId::kStar, ShapeId::kCrescent, ShapeId::kArrow})
    for (const Line line : {Line{20.0, 3, 0.3}, Line{250.0, 2, 1.9}, Line{30.0, 5, -0.8}})
    {
      DrawnScene scene = drawScene(id, 0.4 + 1.1 * static_cast<int>(id), 0.8);
      const cv::Point2d centre = deepestPoint(scene.truth, scene.image.size());
      const cv::Point2d along(std::cos(line.angle), std::sin(line.angle));
      cv::line(scene.image, centre - 400.0 * along, centre + 400.0 * along, cv::Scalar(line.grey), line.width,
               cv::LINE_AA);
      const std::string what = amcr_test::shapeName(id) + " crossed by a line of grey " +
                               std::to_string(static_cast<int>(line.grey)) + ", " + std::to_string(line.width) + " px";
      const amcr::CutShape cut = amcr::cutShape(scene.image, regionAround(scene.truth), amcr::Params());
      ASSERT_TRUE(cut.ok()) << what << ": " << cut.why;
      const Comparison c = compare(cut, scene.truth, scene.image.size());
      std::cout << "[ cut      ] " << what << ": IoU " << c.iou << ", area ratio " << c.area_ratio << "\n";
      EXPECT_GE(c.iou, 0.85) << what;
      EXPECT_NEAR(c.area_ratio, 1.0, 0.12) << what;
    }
}

// Bad regions and images: no shape, and a reason naming the problem.

amcr::CutShape cutFromGrey(const std::vector<cv::Point2f>& region)
{
  const cv::Mat image(120, 160, CV_8UC1, cv::Scalar(128));
  return amcr::cutShape(image, region, amcr::Params());
}

void expectFailure(const amcr::CutShape& cut, const std::string& reason, const std::string& what)
{
  EXPECT_FALSE(cut.ok()) << what;
  EXPECT_TRUE(cut.silhouette.empty()) << what;
  EXPECT_NE(cut.why.find(reason), std::string::npos) << what << ": '" << cut.why << "' lacks '" << reason << "'";
}

TEST(RegionShape, BadRegionsSayWhy)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::set<std::string> reasons;
  const auto check = [&](const amcr::CutShape& cut, const std::string& reason, const std::string& what) {
    expectFailure(cut, reason, what);
    reasons.insert(cut.why);
  };
  check(cutFromGrey({{10, 10}, {50, 50}}), "at least 3 points", "2 points");
  check(cutFromGrey({}), "at least 3 points", "no points");
  check(cutFromGrey(amcr::rectangleRegion(10, 10, 0, 50)), "zero area", "zero width");
  check(cutFromGrey({{10, 10}, {30, 30}, {60, 60}}), "zero area", "collinear");
  check(cutFromGrey({{10, 10}, {nan, 30}, {60, 10}}), "not finite", "NaN");
  check(cutFromGrey({{10, 10}, {inf, 30}, {60, 10}}), "not finite", "infinity");
  check(cutFromGrey(amcr::rectangleRegion(200, 10, 50, 50)), "outside the image", "right of the image");
  check(cutFromGrey(amcr::rectangleRegion(-100, -100, 60, 60)), "outside the image", "above left");
  check(cutFromGrey(amcr::rectangleRegion(-1e6, -1e6, 2e6, 10)), "outside the image", "huge, above");
  check(cutFromGrey(amcr::rectangleRegion(10, 10, 4, 4)), "too small", "4 x 4 px");
  check(cutFromGrey(amcr::rectangleRegion(10, 10, 100, 80)), "no edges", "uniform grey");
  // Distinct texts for distinct problems (one reason per problem above, the
  // point counts, point indices and the image size aside).
  EXPECT_GE(reasons.size(), 7u);
}

TEST(RegionShape, HugeRegionCoveringTheImageIsClipped)
{
  cv::Mat image(120, 160, CV_8UC1, cv::Scalar(190));
  cv::circle(image, {80, 60}, 30, cv::Scalar(30), cv::FILLED);
  const amcr::CutShape cut = amcr::cutShape(image, amcr::rectangleRegion(-1e9, -1e9, 2e9, 2e9), amcr::Params());
  ASSERT_TRUE(cut.ok()) << cut.why;
  EXPECT_NEAR(cv::countNonZero(cut.silhouette), M_PI * 30 * 30, 0.05 * M_PI * 30 * 30);
}

TEST(RegionShape, OpenLinesAreNoOutline)
{
  cv::Mat image(200, 200, CV_8UC1, cv::Scalar(180));
  // A bent stroke inside the region, clear of its border.
  cv::polylines(image, std::vector<std::vector<cv::Point>>{{{40, 150}, {100, 40}, {160, 150}}}, false, cv::Scalar(30),
                3, cv::LINE_AA);
  expectFailure(amcr::cutShape(image, amcr::rectangleRegion(10, 10, 180, 180), amcr::Params()), "no closed outline",
                "a bent stroke");
  // A thick line across the region: it touches the region's border.
  cv::Mat across(200, 200, CV_8UC1, cv::Scalar(180));
  cv::line(across, {0, 60}, {199, 140}, cv::Scalar(30), 12);
  expectFailure(amcr::cutShape(across, amcr::rectangleRegion(10, 10, 180, 180), amcr::Params()), "no closed outline",
                "a thick line across");
}

TEST(RegionShape, BadImagesSayWhy)
{
  const std::vector<cv::Point2f> region = amcr::rectangleRegion(10, 10, 50, 50);
  expectFailure(amcr::cutShape(cv::Mat(), region, amcr::Params()), "image is empty", "empty image");
  expectFailure(amcr::cutShape(cv::Mat(100, 100, CV_32FC1, cv::Scalar(0.5)), region, amcr::Params()), "type",
                "float image");
  expectFailure(amcr::cutShape(cv::Mat(100, 100, CV_8UC4, cv::Scalar::all(9)), region, amcr::Params()), "type",
                "4 channels");
}
}  // namespace

// A part with inner edges (the drawn grey template's body, its disc and bar)
// is cut as a grey template too: the prototype taught from the cut keeps the
// disc's edge, which the silhouette of its outline does not have. A plain
// shape is cut as a silhouette only, as before.
TEST(RegionShape, APartWithInnerEdgesIsCutAsAGreyTemplate)
{
  amcr_test::Clutter clutter;
  clutter.lines = 0;
  clutter.noise_sigma = 2.0;
  clutter.seed = 31;
  const cv::Point2d template_centre(0.5 * (amcr_test::kTemplateSide - 1), 0.5 * (amcr_test::kTemplateSide - 1));
  const amcr::Affine truth = amcr_test::makeAffine(template_centre, {320, 240}, 0.3, 1.0, 1.0, 0.0);
  const cv::Mat image =
      amcr_test::templateOverClutter(amcr_test::TemplateView::kPart, truth, clutter, 1).front();
  const cv::Rect body = amcr_test::kTemplateBody;
  const std::vector<cv::Point2d> corners = amcr_test::transformPoints(
      truth, {cv::Point2d(body.x, body.y), cv::Point2d(body.br().x, body.y), cv::Point2d(body.br().x, body.br().y),
              cv::Point2d(body.x, body.br().y)});
  const amcr::CutShape cut = amcr::cutShape(image, regionAround(corners), amcr::Params());
  ASSERT_TRUE(cut.ok()) << cut.why;
  ASSERT_EQ(cut.grey_template.type(), CV_8UC4);
  ASSERT_EQ(cut.grey_template.size(), cut.silhouette.size());
  cv::Mat alpha;
  cv::extractChannel(cut.grey_template, alpha, 3);
  EXPECT_EQ(cv::countNonZero(alpha != cut.silhouette), 0) << "the alpha channel is the silhouette";

  const amcr::Params params;
  const amcr::Prototype taught("part", cut.prototypeImage(), params.prototype_size, params.edge_threshold,
                               params.blur_sigma, 1, "", params.edge_full_strength);
  ASSERT_TRUE(taught.isTemplate());
  // The disc's centre in the table: from the image through the cut's box.
  const cv::Point2d disc_in_image = amcr::applyAffine(truth, cv::Point2d(58, 58));
  const cv::Point2d disc_in_cut = disc_in_image - cv::Point2d(cut.bounds.x, cut.bounds.y);
  const cv::Matx23d& m = taught.originalToTable();
  const cv::Point2d disc(m(0, 0) * disc_in_cut.x + m(0, 1) * disc_in_cut.y + m(0, 2),
                         m(1, 0) * disc_in_cut.x + m(1, 1) * disc_in_cut.y + m(1, 2));
  const double radius = 22.0 * m(0, 0);
  int on_disc = 0;
  for (const amcr::OutlinePoint& o : taught.outline())
    on_disc += std::abs(cv::norm(cv::Point2d(o.position) - disc) - radius) <= 2.0 ? 1 : 0;
  EXPECT_GE(on_disc, static_cast<int>(0.7 * M_PI * radius)) << "model points on the disc's edge (radius "
                                                            << radius << " table px)";

  // A plain shape (CutEachShape) has none: the silhouette is what is taught.
  const DrawnScene plain = drawScene(ShapeId::kStar, 0.2, 1.0);
  const amcr::CutShape star = amcr::cutShape(plain.image, regionAround(plain.truth), amcr::Params());
  ASSERT_TRUE(star.ok()) << star.why;
  EXPECT_EQ(star.prototypeImage().data, star.silhouette.data);
}
