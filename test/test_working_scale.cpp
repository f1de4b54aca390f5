// working_scale.h (the filter works on the input reduced to
// working_resolution): the working size chosen for an input,
// and the map of a result from working px back to input px.
#include <cmath>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/homography.h"
#include "amcr/base/params.h"
#include "amcr/extraction/viewing_angle.h"
#include "amcr/working_scale.h"

namespace
{
void expectNear(const cv::Point2d& a, const cv::Point2d& b, const char* what)
{
  EXPECT_NEAR(a.x, b.x, 1e-9) << what;
  EXPECT_NEAR(a.y, b.y, 1e-9) << what;
}

TEST(WorkingScale, ReducesTheLongerSideAndNeverEnlarges)
{
  const amcr::WorkingScale big = amcr::chooseWorkingScale(cv::Size(1280, 720), 640);
  EXPECT_EQ(big.working, cv::Size(640, 360));
  EXPECT_DOUBLE_EQ(big.factor(), 0.5);
  EXPECT_EQ(amcr::chooseWorkingScale(cv::Size(720, 1280), 640).working, cv::Size(360, 640));  // portrait
  EXPECT_EQ(amcr::chooseWorkingScale(cv::Size(1920, 1080), 640).working, cv::Size(640, 360));
  EXPECT_EQ(amcr::chooseWorkingScale(cv::Size(4000, 3), 640).working, cv::Size(640, 1));  // at least 1 px
  for (const cv::Size input : {cv::Size(640, 480), cv::Size(320, 240), cv::Size(5, 5)})
  {
    const amcr::WorkingScale s = amcr::chooseWorkingScale(input, 640);
    EXPECT_TRUE(s.identity()) << input;
    EXPECT_EQ(s.working, input);
    EXPECT_EQ(s.factor(), 1.0);
  }
  EXPECT_TRUE(amcr::chooseWorkingScale(cv::Size(3000, 2000), 0).identity());  // 0: the input's own size
}

// cv::resize's pixel-centre map: the centre of working pixel (0, 0) of a 2x
// reduction is the corner between input pixels (0, 0) and (1, 1).
TEST(WorkingScale, MapsPixelCentresAsResizeDoes)
{
  const amcr::WorkingScale s = amcr::chooseWorkingScale(cv::Size(1280, 960), 640);
  expectNear(amcr::applyAffine(s.toInput(), {0, 0}), {0.5, 0.5}, "origin");
  expectNear(amcr::applyAffine(s.toInput(), {639, 479}), {1278.5, 958.5}, "far corner");
  expectNear(amcr::applyAffine(s.toWorking(), amcr::applyAffine(s.toInput(), {17.25, 3.5})), {17.25, 3.5}, "round trip");
  // A bright 2x2 block at input (100..101, 40..41) is one working pixel at (50, 20).
  cv::Mat input(960, 1280, CV_8UC1, cv::Scalar(0));
  input(cv::Rect(100, 40, 2, 2)).setTo(255);
  const cv::Mat working = amcr::toWorkingImage(input, s);
  ASSERT_EQ(working.size(), cv::Size(640, 480));
  EXPECT_EQ(working.at<uchar>(20, 50), 255);
  EXPECT_EQ(cv::countNonZero(working), 1);
  const cv::Mat same = amcr::toWorkingImage(working, amcr::chooseWorkingScale(working.size(), 640));
  EXPECT_EQ(same.data, working.data);  // the identity does not copy
}

// Every geometric field is mapped by the same map: a prototype point taken
// through the scaled affine (or homography) lands where the scaled working
// point is; the inverse affine goes back; outlines and correspondences move
// with it; the labels, scores and support stay.
TEST(WorkingScale, ScaleResultMapsEveryGeometricFieldConsistently)
{
  const amcr::Affine working_to_input = amcr::chooseWorkingScale(cv::Size(1280, 721), 640).toInput();  // x2, y 721/361
  amcr::RecognizedObject o;
  o.label = "arrow";
  o.prototype_id = 2;
  o.track_id = 7;
  o.score = 0.9;
  o.support = 5;
  o.prototype_to_image = amcr::Affine(0.6, 0.2, 100, -0.1, 0.5, 80);
  ASSERT_TRUE(amcr::invertAffine(o.prototype_to_image, o.image_to_prototype));
  o.homography = amcr::Homography(0.6, 0.2, 100, -0.1, 0.5, 80, 1e-4, -2e-4, 1);
  o.homography_valid = true;
  const std::vector<cv::Point2d> prototype_points = {{0, 0}, {199, 0}, {120, 150}, {10, 190}};
  for (const cv::Point2d& q : prototype_points)
  {
    o.outline.push_back(amcr::applyHomography(o.homography, q));
    o.correspondences.push_back({amcr::applyAffine(o.prototype_to_image, q), q});
  }
  amcr::RecognitionResult working;
  working.iteration = 12;
  working.objects = {o, o};
  working.objects[1].homography_valid = false;
  working.objects[1].homography = amcr::liftAffine(o.prototype_to_image);

  amcr::RecognitionResult input = working;
  amcr::scaleResult(input, working_to_input);
  EXPECT_EQ(input.iteration, 12);
  ASSERT_EQ(input.objects.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k)
  {
    const amcr::RecognizedObject& w = working.objects[k];
    const amcr::RecognizedObject& i = input.objects[k];
    EXPECT_EQ(i.label, w.label);
    EXPECT_EQ(i.track_id, w.track_id);
    EXPECT_EQ(i.score, w.score);
    EXPECT_EQ(i.support, w.support);
    EXPECT_EQ(i.homography_valid, w.homography_valid);
    for (const cv::Point2d& q : prototype_points)
    {
      const cv::Point2d affine_point = amcr::applyAffine(working_to_input, amcr::applyAffine(w.prototype_to_image, q));
      expectNear(amcr::applyAffine(i.prototype_to_image, q), affine_point, "prototype_to_image");
      expectNear(amcr::applyAffine(i.image_to_prototype, affine_point), q, "image_to_prototype");
      expectNear(amcr::applyHomography(i.homography, q),
                 amcr::applyAffine(working_to_input, amcr::applyHomography(w.homography, q)), "homography");
    }
    EXPECT_DOUBLE_EQ(i.homography(2, 2), 1.0);
    if (!i.homography_valid)
    {
      EXPECT_EQ(i.homography, amcr::liftAffine(i.prototype_to_image)) << "the lift of the affine";
    }
    ASSERT_EQ(i.outline.size(), w.outline.size());
    for (std::size_t j = 0; j < w.outline.size(); ++j)
      expectNear(i.outline[j], amcr::applyAffine(working_to_input, w.outline[j]), "outline");
    ASSERT_EQ(i.correspondences.size(), w.correspondences.size());
    for (std::size_t j = 0; j < w.correspondences.size(); ++j)
    {
      expectNear(i.correspondences[j].image, amcr::applyAffine(working_to_input, w.correspondences[j].image),
                 "correspondence, image side");
      expectNear(i.correspondences[j].prototype, w.correspondences[j].prototype, "correspondence, prototype side");
    }
    EXPECT_DOUBLE_EQ(i.anisotropy, amcr::affineAnisotropy(i.prototype_to_image));
    EXPECT_DOUBLE_EQ(i.viewing_angle_deg, amcr::viewingAngleDegrees(i.anisotropy));
  }
}

TEST(WorkingScale, OutOfRangeIsAParameterErrorNamingIt)
{
  for (const int value : {-1, 4001})
  {
    amcr::Params p;
    p.working_resolution = value;
    try
    {
      p.validate();
      ADD_FAILURE() << value << " accepted";
    }
    catch (const amcr::ParameterError& e)
    {
      EXPECT_NE(std::string(e.what()).find("working_resolution"), std::string::npos) << e.what();
    }
  }
  amcr::Params p;
  EXPECT_EQ(p.working_resolution, 640);
  p.working_resolution = 0;
  EXPECT_NO_THROW(p.validate());
}
}  // namespace
