// Recognition of an instance not in the memory, i.e. of a class by its
// instances (the label is the class): the memory holds
// two instances of a label, each deformed one way from a shape, and other
// labels; the scene shows the shape itself, halfway between the two. The
// label must be reported, and no other.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/recognizer.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kFrames = 60;
// Radial deformation of the two stored instances, share of the radius. The
// outline verification (2 px) limits it: at 8% and 12% the star and the
// arrow are still found, the crescent (thin horns) never is (measured).
constexpr double kDeformation = 0.05;

/// `shape`'s outline with every point's distance to the image centre scaled
/// by 1 + t * kDeformation * cos(3 angle + 0.7): a three-lobed change of
/// shape that no affine map undoes; t = -1 and +1 are the stored instances,
/// t = 0 the shape itself.
std::vector<cv::Point2d> deformed(ShapeId shape, double t)
{
  const cv::Point2d c = amcr_test::prototypeCentre();
  std::vector<cv::Point2d> out;
  for (const cv::Point2d& p : amcr_test::shapePolygon(shape))
  {
    const double angle = std::atan2(p.y - c.y, p.x - c.x);
    const double f = 1.0 + t * kDeformation * std::cos(3.0 * angle + 0.7);
    out.emplace_back(c.x + f * (p.x - c.x), c.y + f * (p.y - c.y));
  }
  return out;
}

struct Case
{
  ShapeId shape;
  std::uint64_t clutter_seed;
};

void PrintTo(const Case& c, std::ostream* os) { *os << amcr_test::shapeName(c.shape) << " " << c.clutter_seed; }

class UnseenInstance : public ::testing::TestWithParam<Case>
{
};

TEST_P(UnseenInstance, IsReportedWithItsNeighboursLabel)
{
  const Case c = GetParam();
  const std::string label = amcr_test::shapeName(c.shape);
  amcr::Params params;
  params.seed = 1;
  params.table_cache_dir = "none";
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (ShapeId other : amcr_test::allShapes())
  {
    const std::string name = amcr_test::shapeName(other);
    if (other != c.shape)
      memory->add(name, amcr_test::drawPrototype(other), params);
    else  // only the two deformed neighbours: the shape itself is not in memory
      for (double t : {-1.0, 1.0})
        memory->add(name, amcr_test::drawSilhouette(deformed(other, t)), params, name + (t < 0 ? "/minus" : "/plus"));
  }

  amcr_test::Scene scene;
  const amcr::Affine truth =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.6, 0.75, 0.7, 0.1);
  scene.objects.push_back({c.shape, truth});  // the shape itself: t = 0
  scene.clutter.seed = c.clutter_seed;
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, kFrames);

  amcr::Recognizer recognizer(params, memory);
  int first_correct = -1, correct_frames = 0, wrong = 0;
  for (int k = 0; k < kFrames; ++k)
  {
    bool correct = false;
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      if (o.label != label)
      {
        ++wrong;
        continue;
      }
      // The stored instances differ from the shown shape by up to 12% of the radius: the place, not the pose, is checked.
      const cv::Point2d centre = amcr::applyAffine(o.prototype_to_image, amcr_test::prototypeCentre());
      correct = correct || std::hypot(centre.x - 320, centre.y - 240) < 15.0;
    }
    if (correct && first_correct < 0)
      first_correct = k + 1;
    correct_frames += correct;
  }
  std::cout << "[ unseen   ] " << label << " (clutter seed " << c.clutter_seed << "): first at " << first_correct
            << ", in " << correct_frames << " of " << kFrames << " frames, " << wrong << " other reports\n";
  EXPECT_GT(first_correct, 0) << "the unseen " << label << " was never reported";
  EXPECT_EQ(wrong, 0) << "other labels were reported";
}

INSTANTIATE_TEST_SUITE_P(Shapes, UnseenInstance,
                         ::testing::Values(Case{ShapeId::kStar, 11}, Case{ShapeId::kArrow, 12},
                                           Case{ShapeId::kCrescent, 13}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return amcr_test::shapeName(info.param.shape) + "_" +
                                  std::to_string(info.param.clutter_seed);
                         });
}  // namespace
