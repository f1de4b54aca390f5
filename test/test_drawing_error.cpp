// A prototype drawn a few percent off: a user who draws a printed target from
// measurements with a ruler gets its aspect, its holes' places and sizes a few
// percent wrong. The real target over clutter must still be found within 20
// frames, with the prototype drawn 3% and 5% off (recognizer seeds 1-5; 1-2
// under the sanitizers, test/run_length.h):
// the holes fitted on their own (part_shift, outline_parts.h) make up for it.
#include <cmath>
#include <iostream>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kFindWithin = 20;        // frames
constexpr double kCentreTolerance = 6.0;  // px: the reported target's centre from the truth's

/// A printed target, white on black as a prototype image: a rectangle of
/// `aspect` (width / height; the height 110 px) with a disc and two dots cut
/// out, their centres (in the rectangle's normalised coordinates) shifted by
/// `shift` and their radii scaled by `scale`.
cv::Mat target(double aspect, double shift, double scale)
{
  const double h = 110, w = aspect * h;
  const cv::Point2d corner = amcr_test::prototypeCentre() - cv::Point2d(w / 2, h / 2);
  const auto at = [&](double x, double y) { return corner + cv::Point2d((x + shift) * w, y * h); };
  cv::Mat image(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
  amcr_test::fillPolygon(image, {corner, corner + cv::Point2d(w, 0), corner + cv::Point2d(w, h), corner + cv::Point2d(0, h)},
                         255);
  amcr_test::fillPolygon(image, amcr_test::wavyOval(at(0.62, 0.5), 26 * scale, 26 * scale, 0.0), 0);
  amcr_test::fillPolygon(image, amcr_test::wavyOval(at(0.18, 0.25), 8 * scale, 8 * scale, 0.0), 0);
  amcr_test::fillPolygon(image, amcr_test::wavyOval(at(0.18, 0.75), 8 * scale, 8 * scale, 0.0), 0);
  return image;
}

const cv::Mat& trueTarget()
{
  static const cv::Mat t = target(1.3, 0.0, 1.0);
  return t;
}

/// The memory: three drawn silhouettes and the target drawn `error` off
/// (aspect larger, holes shifted and smaller, each by `error`).
std::shared_ptr<const amcr::PrototypeMemory> memoryWithTargetOff(double error)
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (const ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
    memory->add(amcr_test::shapeName(id), amcr_test::drawPrototype(id), amcr::Params());
  memory->add("target", target(1.3 * (1.0 + error), error, 1.0 - error), amcr::Params());
  return memory;
}

/// kFindWithin frames of the true target printed dark over clutter (about
/// 130 px across), each with its own noise.
std::vector<cv::Mat> frames(std::uint64_t seed, amcr::Affine& truth)
{
  truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.5, 0.9, 0.9, 0.05);
  amcr_test::Clutter clutter;
  clutter.random_shapes = 6;
  clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  clutter.seed = seed;
  return amcr_test::printedOverClutter(trueTarget(), truth, clutter, kFindWithin);
}

/// The first frame (1-based) of `sequence` reporting "target" with its
/// centre near the truth's, or 0.
int firstFound(const std::vector<cv::Mat>& sequence, const amcr::Affine& truth,
               const std::shared_ptr<const amcr::PrototypeMemory>& memory, std::uint64_t seed, double part_shift)
{
  amcr::Params p;
  p.seed = seed;
  p.part_shift = part_shift;
  amcr::Recognizer recognizer(p, memory);
  const cv::Point2d centre = amcr::applyAffine(truth, amcr_test::prototypeCentre());
  for (int k = 0; k < kFindWithin; ++k)
    for (const amcr::RecognizedObject& o : recognizer.step(sequence[k]).objects)
    {
      const cv::Point2d at = amcr::applyAffine(o.prototype_to_image, amcr_test::prototypeCentre());
      if (o.label == "target" && std::hypot(at.x - centre.x, at.y - centre.y) <= kCentreTolerance)
        return k + 1;
    }
  return 0;
}
}  // namespace

TEST(DrawingError, ATargetDrawnThreeAndFivePercentOffIsFound)
{
  // Measured (20 frames): 3% off found by seeds 1-5 (frames 3-8), 5% off by
  // seeds 2-5 (frames 3-8); seed 1 does not find the 5% one in 60 frames.
  // With the holes fixed to the outline (part_shift 0): 5 and 0 of 5.
  constexpr int kMaxMisses = 1;  // seeds that do not find it, of each error's
  const int seeds = amcr_test::runLength(5, 2);
  // One scene per seed (its clutter and noise), shared by both errors and both settings.
  std::vector<std::vector<cv::Mat>> scenes(seeds);
  amcr::Affine truth;
  for (int s = 0; s < seeds; ++s)
    scenes[s] = frames(601 + s, truth);
  int fixed_found = 0, found_total = 0;
  for (double error : {0.03, 0.05})
  {
    const auto memory = memoryWithTargetOff(error);
    int seeds_found = 0;
    for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed)
    {
      const std::vector<cv::Mat>& sequence = scenes[seed - 1];
      const int found = firstFound(sequence, truth, memory, seed, amcr::Params().part_shift);
      const int fixed = firstFound(sequence, truth, memory, seed, 0.0);
      seeds_found += found > 0;
      fixed_found += fixed > 0;
      std::cout << "[ drawing  ] prototype " << 100 * error << "% off, seed " << seed << ": "
                << (found > 0 ? "found at frame " + std::to_string(found) : std::string("not found"))
                << " (with the holes fixed to the outline: "
                << (fixed > 0 ? "frame " + std::to_string(fixed) : std::string("not found")) << ")" << std::endl;
    }
    found_total += seeds_found;
    EXPECT_GE(seeds_found, seeds - kMaxMisses) << "prototype " << 100 * error << "% off: found by " << seeds_found
                                               << " of seeds 1-" << seeds << " within " << kFindWithin << " frames";
  }
  EXPECT_GT(found_total, fixed_found) << "the holes fitted on their own found no more than the fixed outline: the "
                                         "scene does not test them";
}
