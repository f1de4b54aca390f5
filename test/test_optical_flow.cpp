// The optical flow at sparse points and the track registry: a
// known image motion is recovered, a jump fails the flow, and track ids
// follow outline overlap and are never reused.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/extraction/optical_flow.h"
#include "amcr/extraction/track_registry.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

cv::Mat sceneWithArrow(const amcr::Affine& pose, std::uint64_t clutter_seed)
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kArrow, pose});
  scene.clutter.seed = clutter_seed;
  return amcr_test::renderClean(scene);
}

const amcr::Affine kPose = amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.4, 0.8, 0.7, 0.1);

TEST(PyramidFlow, RecoversAShiftedAndRotatedFrame)
{
  const cv::Mat first = sceneWithArrow(kPose, 7);
  // The whole frame turned by 3 degrees about (300, 250) and shifted by (4, -3) px.
  const cv::Mat rotation = cv::getRotationMatrix2D(cv::Point2f(300, 250), 3.0, 1.0);
  cv::Matx23d motion(reinterpret_cast<const double*>(rotation.data));
  motion(0, 2) += 4.0;
  motion(1, 2) -= 3.0;
  cv::Mat second;
  cv::warpAffine(first, second, cv::Mat(motion), first.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);

  amcr::PyramidFlow flow(21, 3, 40.0);
  EXPECT_FALSE(flow.ready());
  flow.push(first);
  EXPECT_TRUE(flow.track({{10.f, 10.f}}).size() == 1 && !flow.track({{10.f, 10.f}})[0].ok) << "no flow before two frames";
  flow.push(second);
  ASSERT_TRUE(flow.ready());

  // Points on the arrow's outline, where the image has edges.
  std::vector<cv::Point2f> from;
  for (const auto& p : amcr_test::transformPoints(kPose, amcr_test::shapePolygon(ShapeId::kArrow)))
    from.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  const std::vector<amcr::FlowVector> moved = flow.track(from);
  amcr::Affine estimated;
  ASSERT_TRUE(amcr::estimatePatchMotion(from, moved, static_cast<int>(from.size() / 2), estimated));
  for (const auto& p : from)
  {
    const cv::Point2d truth = amcr::applyAffine(motion, cv::Point2d(p));
    const cv::Point2d found = amcr::applyAffine(estimated, cv::Point2d(p));
    EXPECT_NEAR(found.x, truth.x, 0.5);
    EXPECT_NEAR(found.y, truth.y, 0.5);
  }
  EXPECT_NEAR(std::atan2(estimated(1, 0), estimated(0, 0)) * 180.0 / M_PI, 3.0 * -1.0, 0.3)
      << "getRotationMatrix2D turns counter-clockwise on screen, i.e. -3 degrees in image axes";
}

TEST(PyramidFlow, AJumpOrANewSizeFails)
{
  amcr::PyramidFlow flow(21, 3, 20.0);
  flow.push(sceneWithArrow(kPose, 7));
  flow.push(sceneWithArrow(amcr_test::makeAffine(amcr_test::prototypeCentre(), {150, 350}, 2.0, 0.6, 0.6, 0.0), 8));
  std::vector<cv::Point2f> from;
  for (const auto& p : amcr_test::transformPoints(kPose, amcr_test::shapePolygon(ShapeId::kArrow)))
    from.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  int ok = 0;
  for (const auto& f : flow.track(from))
    ok += f.ok;
  EXPECT_LT(ok, static_cast<int>(from.size()) / 2) << "most flows must fail across a jump";
  amcr::Affine motion;
  EXPECT_FALSE(amcr::estimatePatchMotion(from, flow.track(from), static_cast<int>(from.size() / 2), motion));

  flow.push(cv::Mat(240, 320, CV_8UC1, cv::Scalar(128)));
  EXPECT_FALSE(flow.ready()) << "a new size forgets the previous frame";
}

TEST(PyramidFlow, BadArgumentsAreErrors)
{
  EXPECT_THROW(amcr::PyramidFlow(1, 3, 40.0), amcr::ParameterError);
  EXPECT_THROW(amcr::PyramidFlow(21, -1, 40.0), amcr::ParameterError);
  EXPECT_THROW(amcr::PyramidFlow(21, 3, 0.0), amcr::ParameterError);
  amcr::PyramidFlow flow(21, 3, 40.0);
  EXPECT_THROW(flow.push(cv::Mat()), amcr::InputError);
  EXPECT_THROW(flow.push(cv::Mat(10, 10, CV_32FC1)), amcr::InputError);
}

amcr::RecognizedObject objectAt(int prototype, const amcr::Affine& pose)
{
  amcr::RecognizedObject o;
  o.prototype_id = prototype;
  o.label = "shape " + std::to_string(prototype);  // one label per prototype
  o.prototype_to_image = pose;
  o.outline = amcr_test::transformPoints(pose, amcr_test::shapePolygon(ShapeId::kStar));
  return o;
}

amcr::Affine shifted(double dx)
{
  return amcr_test::makeAffine(amcr_test::prototypeCentre(), {200 + dx, 200}, 0.0, 0.5, 0.5, 0.0);
}

TEST(OutlineOverlap, IdenticalIsOneAndDisjointIsZero)
{
  const auto a = objectAt(0, shifted(0)).outline;
  EXPECT_NEAR(amcr::outlineOverlap(a, a), 1.0, 1e-9);
  EXPECT_EQ(amcr::outlineOverlap(a, objectAt(0, shifted(300)).outline), 0.0);
  const double half = amcr::outlineOverlap(a, objectAt(0, shifted(20)).outline);
  EXPECT_GT(half, 0.1);
  EXPECT_LT(half, 0.9);
  EXPECT_EQ(amcr::outlineOverlap({}, a), 0.0);
}

TEST(TrackRegistry, IdsFollowOverlapAndAreNeverReused)
{
  amcr::TrackRegistry registry;
  std::vector<amcr::RecognizedObject> frame = {objectAt(0, shifted(0)), objectAt(0, shifted(250))};
  registry.assign(frame);
  EXPECT_EQ(frame[0].track_id, 1);
  EXPECT_EQ(frame[1].track_id, 2);

  // Both move a little, in the other order: each keeps its id.
  std::vector<amcr::RecognizedObject> next = {objectAt(0, shifted(255)), objectAt(0, shifted(4))};
  registry.assign(next);
  EXPECT_EQ(next[0].track_id, 2);
  EXPECT_EQ(next[1].track_id, 1);

  // A prediction by the flow keeps a fast object on its track.
  registry.move(1, amcr::Affine(1, 0, 60, 0, 1, 0));
  std::vector<amcr::RecognizedObject> fast = {objectAt(0, shifted(64))};
  registry.assign(fast);
  EXPECT_EQ(fast[0].track_id, 1);

  // Another prototype at the same place is another object; after clear()
  // the ids go on counting.
  std::vector<amcr::RecognizedObject> other = {objectAt(1, shifted(64))};
  registry.assign(other);
  EXPECT_EQ(other[0].track_id, 3);
  registry.clear();
  std::vector<amcr::RecognizedObject> again = {objectAt(1, shifted(64))};
  registry.assign(again);
  EXPECT_EQ(again[0].track_id, 4);
}
}  // namespace
