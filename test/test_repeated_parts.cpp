// Many copies of one grey template in view, as parts on a tray or LEDs on a
// board: 36 copies of the drawn part (template_drawing.h), any turn, 52-60 px
// across, over scattered lines, are 36 objects at their poses with no other
// report; with max_objects below 36 exactly max_objects are reported and the
// ones found beyond are counted, not dropped in silence.
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"
#include "template_drawing.h"

namespace
{
constexpr int kRows = 6, kColumns = 6;
constexpr int kFrames = 180;             // of the still scene: every copy is reported by then (the last at 150-180)
constexpr double kCornerTolerance = 1.5;  // px, mean over the template image's corners
constexpr double kBoardGrey = 150.0;      // the template's own board
const cv::Size kTemplateSize(amcr_test::kTemplateSide, amcr_test::kTemplateSide);

/// Template px -> image px of each copy: a 6 x 6 grid over 640 x 480, each
/// turned at random, its body 52-60 px across (draws of `seed`).
std::vector<amcr::Affine> copies(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> turn(0.0, 2.0 * M_PI), body(52.0, 60.0), jitter(-4.0, 4.0);
  const cv::Point2d template_centre(0.5 * (amcr_test::kTemplateSide - 1), 0.5 * (amcr_test::kTemplateSide - 1));
  std::vector<amcr::Affine> placed;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kColumns; ++c)
    {
      // Separate statements: the order of a call's arguments is unspecified.
      const double x = 60.0 + c * 104.0 + jitter(rng);
      const double y = 45.0 + r * 78.0 + jitter(rng);
      const double a = turn(rng);
      const double scale = body(rng) / amcr_test::kTemplateBody.width;
      placed.push_back(amcr_test::makeAffine(template_centre, {x, y}, a, scale, scale, 0.0));
    }
  return placed;
}

/// The board with scattered lines, each copy's body warped in (its board margin left out), sensor noise.
cv::Mat scene(const std::vector<amcr::Affine>& placed, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> px(0, 639), py(0, 479), offset(-60, 60), grey(60, 230), width(1, 2);
  cv::Mat image(480, 640, CV_8UC1, cv::Scalar(kBoardGrey));
  for (int k = 0; k < 25; ++k)
  {
    // One draw per statement (a call's arguments are evaluated in an unspecified order), in the
    // order GCC evaluated them, the last first: the scene the test was measured on.
    const int from_y = py(rng);
    const cv::Point from(px(rng), from_y);
    const int dx = offset(rng), dy = offset(rng), g = grey(rng), w = width(rng);
    cv::line(image, from, from + cv::Point(dx, dy), cv::Scalar(g), w, cv::LINE_AA);
  }
  const cv::Mat part = amcr_test::drawGreyTemplate();
  cv::Mat body_mask = cv::Mat::zeros(part.size(), CV_8UC1);
  body_mask(amcr_test::kTemplateBody).setTo(255);
  for (const amcr::Affine& a : placed)
  {
    cv::Mat warped, mask;
    cv::warpAffine(part, warped, cv::Mat(a), image.size(), cv::INTER_AREA);
    cv::warpAffine(body_mask, mask, cv::Mat(a), image.size(), cv::INTER_LINEAR);
    warped.copyTo(image, mask > 127);
  }
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  cv::Mat noise(image.size(), CV_16SC1);
  cv::theRNG().state = seed;
  cv::randn(noise, 0.0, 4.0);
  cv::Mat noisy;
  image.convertTo(noisy, CV_16SC1);
  noisy += noise;
  noisy.convertTo(image, CV_8UC1);
  return image;
}

std::shared_ptr<const amcr::PrototypeMemory> partMemory()
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("part", amcr_test::drawGreyTemplate(), amcr::Params());
  return memory;
}

amcr::Params params(std::uint64_t seed, int max_objects)
{
  amcr::Params p;
  p.seed = seed;
  p.max_objects = max_objects;
  p.min_object_size = 40.0;  // the bodies are 52-60 px: the default (64) is for larger targets
  return p;
}

struct Count
{
  int right = 0;        ///< copies reported within kCornerTolerance (each once)
  int other = 0;        ///< reports that match no copy, or one already matched
  double worst = 0.0;   ///< the largest corner error of a right report
};

Count count(const std::vector<amcr::RecognizedObject>& objects, const std::vector<amcr::Affine>& placed)
{
  Count c;
  std::set<std::size_t> matched;
  for (const amcr::RecognizedObject& o : objects)
  {
    std::size_t best = 0;
    double best_error = HUGE_VAL;
    for (std::size_t k = 0; k < placed.size(); ++k)
    {
      const double e = amcr_test::cornerError(o.prototype_to_image, placed[k], kTemplateSize);
      if (e < best_error)
      {
        best_error = e;
        best = k;
      }
    }
    if (best_error <= kCornerTolerance && matched.insert(best).second)
    {
      ++c.right;
      c.worst = std::max(c.worst, best_error);
    }
    else
      ++c.other;
  }
  return c;
}

TEST(RepeatedParts, ThirtySixCopiesAreThirtySixObjectsAtTheirPoses)
{
  const auto memory = partMemory();
  const std::vector<amcr::Affine> placed = copies(1);
  const cv::Mat image = scene(placed, 1);
  for (const std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2}, 1))
  {
    amcr::Recognizer recognizer(params(seed, 64), memory);
    amcr::RecognitionResult result;
    for (int k = 0; k < kFrames; ++k)
      result = recognizer.step(image);
    const Count c = count(result.objects, placed);
    EXPECT_EQ(c.right, kRows * kColumns) << "seed " << seed;
    EXPECT_EQ(c.other, 0) << "seed " << seed;
    EXPECT_LE(c.worst, kCornerTolerance) << "seed " << seed;
  }
}

TEST(RepeatedParts, BeyondMaxObjectsTheCopiesFoundAreCounted)
{
  constexpr int kLimit = 10;
  const std::vector<amcr::Affine> placed = copies(1);
  const cv::Mat image = scene(placed, 1);
  amcr::Recognizer recognizer(params(1, kLimit), partMemory());
  amcr::RecognitionResult result;
  int over_limit = 0;
  for (int k = 0; k < 60; ++k)
  {
    result = recognizer.step(image);
    EXPECT_LE(static_cast<int>(result.objects.size()), kLimit) << "frame " << k;
    over_limit += result.objects_over_limit;
  }
  const Count c = count(result.objects, placed);
  EXPECT_EQ(c.right, kLimit);
  EXPECT_EQ(c.other, 0);
  EXPECT_GT(over_limit, 0) << "copies found beyond max_objects were not counted";
}
}  // namespace
