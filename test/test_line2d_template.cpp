// The LINE-2D baseline (bench/baselines/line2d.h) on a grey template: the project's drawn part (a dark
// square body with a light disc and a light bar, test/template_drawing.h) is found at its place in a
// drawn frame, and its templates' features lie on its inner edges too: a plain square of the same
// outline does not pass for it, while the body's silhouette finds that square.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "baselines/line2d.h"
#include "baselines/prototype_image.h"
#include "template_drawing.h"

namespace
{
using amcr_test::TemplateView;

const cv::Size kTemplateSize(amcr_test::kTemplateSide, amcr_test::kTemplateSide);
constexpr double kScale = 1.1;  // the part in the frames: 176 px template image, the body 132 px across

// Sizes around the frames' 176 px, so that the template set stays small (2 sizes x 72 turns x 7 stretches).
amcr_bench::Line2dConfig narrowSizes()
{
  amcr_bench::Line2dConfig config;
  config.min_size = 165;
  config.max_size = 185;
  return config;
}

amcr_bench::Line2d& partDetector()
{
  static amcr_bench::Line2d detector({amcr_bench::prototypeImage("part", amcr_test::drawGreyTemplate())},
                                     narrowSizes());
  return detector;
}

amcr::Affine partAt(double turn_deg) { return amcr_test::templatePlacement(turn_deg, {330, 250}, kScale); }

cv::Mat frameOf(TemplateView view, const amcr::Affine& truth) { return amcr_test::templateFrame(view, truth, 5); }

class Line2dTemplateTurn : public testing::TestWithParam<double>
{
};

// Within 12 px on average over the template image's corners (113 px from its centre at 1.1 x): the best
// template is up to 2.5 degrees (5 px there) and a half size step (6%, 7 px) off, on linemod's 5 px grid.
// The disc and the bar fix the turn: a quarter turn off, the corners would be 160 px away.
TEST_P(Line2dTemplateTurn, FindsThePartAtItsPlace)
{
  const amcr::Affine truth = partAt(GetParam());
  const std::vector<amcr_bench::Detection> found = partDetector().detect(frameOf(TemplateView::kPart, truth));
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found[0].label, "part");
  EXPECT_LT(amcr_test::cornerError(found[0].prototype_to_image, truth, kTemplateSize), 12.0);
}

INSTANTIATE_TEST_SUITE_P(Turns, Line2dTemplateTurn, testing::Values(0.0, 37.0, 110.0, 251.0));

// The plain square has the part's outline and none of its inner edges: with features on the outline
// alone the part's templates would match it as well as the part itself.
TEST(Line2dTemplate, PlainSquareOfTheSameOutlineIsNotThePart)
{
  const amcr::Affine truth = partAt(37.0);
  EXPECT_TRUE(partDetector().detect(frameOf(TemplateView::kPlain, truth)).empty());

  // The square itself is there to be found: the body's silhouette finds it.
  amcr_bench::Line2d square({amcr_bench::prototypeImage("square", amcr_test::drawTemplateOutline())}, narrowSizes());
  const std::vector<amcr_bench::Detection> found = square.detect(frameOf(TemplateView::kPlain, truth));
  ASSERT_FALSE(found.empty());
  EXPECT_EQ(found[0].label, "square");
}
}  // namespace
