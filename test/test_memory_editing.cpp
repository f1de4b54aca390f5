// The memory edited at runtime (~teach and ~remove_prototype):
// PrototypeMemory::remove and isPrefixOf, and Recognizer::extendMemory, which
// adds prototypes to a running filter without a reset. End to end: a shape the
// memory does not hold is cut from a frame (amcr::cutShape), taught, and then
// recognized in frames that show it under another pose. A memory made ready
// on another thread while the recognizer runs (amcr::FilterMemory) is swapped
// in with the same outcome as one built by the swap itself.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/recognizer.h"
#include "amcr/memory/region_shape.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

amcr::Params testParams()
{
  amcr::Params params;
  params.seed = 3;
  params.table_cache_dir = "none";
  return params;
}

TEST(MemoryEditing, RemoveTakesEveryInstanceOfALabel)
{
  const amcr::Params params = testParams();
  amcr::PrototypeMemory memory;
  memory.add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), params);
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar), params, "star/a.png");
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar, false), params, "star/b.png");
  memory.add("flag", amcr_test::drawPrototype(ShapeId::kFlag), params);
  const amcr::PrototypeMemory before = memory;

  EXPECT_EQ(memory.remove("star"), 2u);
  ASSERT_EQ(memory.size(), 2u);
  EXPECT_EQ(memory.labels(), (std::vector<std::string>{"arrow", "flag"}));
  EXPECT_EQ(memory.find("flag"), 1);  // moved down
  EXPECT_EQ(memory.find("star"), -1);
  EXPECT_EQ(memory.remove("star"), 0u);  // unknown now: nothing changes
  EXPECT_EQ(memory.size(), 2u);
  EXPECT_EQ(before.size(), 4u) << "the copy shares the prototypes, not the list";
}

TEST(MemoryEditing, AnExtendedCopyStartsWithTheSamePrototypes)
{
  const amcr::Params params = testParams();
  auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent}, params);
  amcr::PrototypeMemory extended = *memory;
  extended.add("star", amcr_test::drawPrototype(ShapeId::kStar), params);
  EXPECT_TRUE(memory->isPrefixOf(extended));
  EXPECT_TRUE(memory->isPrefixOf(*memory));
  EXPECT_FALSE(extended.isPrefixOf(*memory));
  // The same images loaded again are other prototypes: not an extension.
  auto again = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, params);
  EXPECT_FALSE(memory->isPrefixOf(*again));
}

// A star the memory does not hold is in view. Cut from frame 10 and taught,
// it is recognized under another pose in the frames after, while the filter
// goes on (no reset: the iteration count goes on too).
TEST(MemoryEditing, AShapeTaughtFromAFrameIsRecognizedUnderAnotherPose)
{
  const amcr::Params params = testParams();
  auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent}, params);
  amcr::Recognizer recognizer(params, memory);

  amcr_test::Scene scene;
  const amcr::Affine shown = amcr_test::makeAffine(amcr_test::prototypeCentre(), {300, 230}, 0.3, 0.9, 0.9, 0.0);
  scene.objects = {{ShapeId::kStar, shown}};
  scene.clutter.seed = 4;
  scene.clutter.lines = 0;  // a line across the shape joins its outline to the region's border (region_shape.h)
  const std::vector<cv::Mat> before = amcr_test::renderSequence(scene, 10);
  amcr::RecognitionResult result;
  for (const cv::Mat& frame : before)
    result = recognizer.step(frame);
  ASSERT_EQ(result.iteration, 10);

  // The region: the star's bounding box in the frame and 12 px around it.
  std::vector<cv::Point2d> outline = amcr_test::transformPoints(shown, amcr_test::shapePolygon(ShapeId::kStar));
  std::vector<cv::Point2f> points(outline.begin(), outline.end());
  const cv::Rect box = cv::boundingRect(points);
  const amcr::CutShape cut = amcr::cutShape(
      before.back(), amcr::rectangleRegion(box.x - 12, box.y - 12, box.width + 24, box.height + 24), params);
  ASSERT_TRUE(cut.ok()) << cut.why;

  auto extended = std::make_shared<amcr::PrototypeMemory>(*memory);
  extended->add("taught", cut.silhouette, params);
  recognizer.extendMemory(extended);
  EXPECT_EQ(&recognizer.memory(), extended.get());

  // The star moved, turned and shrank. The taught prototype's px are the frame's, shifted by the
  // cut's offset: its truth is moved * shown^-1 * (that shift).
  const amcr::Affine moved = amcr_test::makeAffine(amcr_test::prototypeCentre(), {380, 250}, -0.5, 0.75, 0.8, 0.1);
  const amcr::Affine offset(1, 0, cut.bounds.x, 0, 1, cut.bounds.y);
  amcr::Affine shown_inverse;
  ASSERT_TRUE(amcr::invertAffine(shown, shown_inverse));
  const amcr::Affine truth = amcr::composeAffine(offset, amcr::composeAffine(shown_inverse, moved));
  scene.objects = {{ShapeId::kStar, moved}};
  scene.clutter.seed = 5;
  const std::vector<cv::Mat> after = amcr_test::renderSequence(scene, 60);
  int found = -1;
  double error = 0.0;
  for (int k = 0; k < static_cast<int>(after.size()) && found < 0; ++k)
  {
    result = recognizer.step(after[k]);
    if (k == 0)
    {
      EXPECT_EQ(result.iteration, 11) << "teaching restarted the filter";
    }
    for (const amcr::RecognizedObject& o : result.objects)
      if (o.label == "taught")
      {
        error = amcr_test::cornerError(o.prototype_to_image, truth, cut.silhouette.size());
        if (error < 6.0)
          found = k + 1;
      }
  }
  EXPECT_GT(found, 0) << "the taught star was not recognized under its new pose within 60 frames (last corner error "
                      << error << " px)";
  RecordProperty("frames_to_recognition", found);
  std::cout << "[ taught   ] star recognized " << found << " frames after teaching, corner error " << error << " px\n";
}

TEST(MemoryEditing, AMemoryThatDoesNotExtendIsRefusedAndTheFilterGoesOn)
{
  const amcr::Params params = testParams();
  auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent}, params);
  amcr::Recognizer recognizer(params, memory);
  amcr_test::Scene scene;
  scene.objects = {{ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.2, 1.0, 1.0, 0.0)}};
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, 3);
  recognizer.step(frames[0]);
  recognizer.step(frames[1]);

  auto other = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, params);
  EXPECT_THROW(recognizer.extendMemory(other), amcr::MemoryError);
  EXPECT_THROW(recognizer.extendMemory(nullptr), amcr::MemoryError);
  EXPECT_EQ(&recognizer.memory(), memory.get());
  EXPECT_EQ(recognizer.step(frames[2]).iteration, 3);
}

amcr_test::Scene arrowScene()
{
  amcr_test::Scene scene;
  scene.objects = {{ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.2, 1.0, 1.0, 0.0)}};
  return scene;
}

// One recognizer builds the new memory's indexes in setMemory; the other gets them made ready on a
// thread while it goes on recognizing. From the swap on, both give the same output.
TEST(MemoryEditing, AMemoryMadeReadyOnAnotherThreadGivesTheSameOutput)
{
  const amcr::Params params = testParams();
  auto memory = amcr_test::drawnMemory({ShapeId::kCrescent, ShapeId::kStar}, params);
  auto next = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, params);
  amcr::Recognizer built_in_the_swap(params, memory), made_ready(params, memory);
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(arrowScene(), 12);

  std::unique_ptr<amcr::FilterMemory> ready;
  std::thread building([&] { ready = std::make_unique<amcr::FilterMemory>(params, next); });
  for (int k = 0; k < 3; ++k)
    made_ready.step(frames[k]);  // meanwhile
  building.join();
  built_in_the_swap.setMemory(next);
  const amcr::FilterMemory replaced = made_ready.setMemory(std::move(*ready));
  EXPECT_EQ(replaced.memory().get(), memory.get()) << "the replaced memory is handed back";
  EXPECT_EQ(&made_ready.memory(), next.get());

  for (int k = 3; k < 12; ++k)
  {
    const amcr::RecognitionResult a = built_in_the_swap.step(frames[k]), b = made_ready.step(frames[k]);
    EXPECT_EQ(a.iteration, b.iteration);
    ASSERT_EQ(a.objects.size(), b.objects.size()) << "frame " << k;
    for (std::size_t i = 0; i < a.objects.size(); ++i)
    {
      EXPECT_EQ(a.objects[i].label, b.objects[i].label);
      EXPECT_EQ(a.objects[i].score, b.objects[i].score);
    }
  }
}

// A memory made ready for other parameters would not fit the filter: refused, and the filter goes on.
TEST(MemoryEditing, AMemoryMadeReadyForOtherParametersIsRefused)
{
  const amcr::Params params = testParams();
  auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent}, params);
  amcr::Recognizer recognizer(params, memory);
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(arrowScene(), 2);
  recognizer.step(frames[0]);

  amcr::Params other = params;
  other.sigma_w = 7.5;
  auto extended = std::make_shared<amcr::PrototypeMemory>(*memory);
  extended->add("star", amcr_test::drawPrototype(ShapeId::kStar), params);
  EXPECT_THROW(recognizer.setMemory(amcr::FilterMemory(other, extended)), amcr::ParameterError);
  EXPECT_THROW(recognizer.extendMemory(amcr::FilterMemory(other, extended)), amcr::ParameterError);
  EXPECT_EQ(&recognizer.memory(), memory.get());
  EXPECT_EQ(recognizer.step(frames[1]).iteration, 2);
}
}  // namespace
