// End to end, a report must explain the image better than a simpler shape
// (generic_rivals.h): with an apple in memory, a round blob over clutter is
// not reported as the apple, although the apple's body lies on its edge all
// round (the stem, 14 % of the outline, on none); the apple itself is, with
// its stem where it is (a round body alone does not tell its turn).
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

constexpr int kFrames = 60;

/// kFrames frames of clutter with an apple (`stem`) or the disc of its body
/// printed at `truth` (120 px across), each frame with its own noise.
std::vector<cv::Mat> appleFrames(bool stem, std::uint64_t seed, amcr::Affine& truth)
{
  truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {300, 250}, 0.3, 0.8, 0.8, 0.0);
  return amcr_test::printedOverClutter(amcr_test::drawApple(stem), truth, amcr_test::distractorClutter(seed), kFrames);
}

/// Frames in which "apple" is reported with its body's centre within 6 px
/// of the truth's (any turn: a disc has none), and, with `upright`, its stem's
/// tip too: the pose is right only with the stem where it is.
int appleReports(const std::vector<cv::Mat>& frames, const amcr::Affine& truth, const amcr::Params& p,
                 bool upright = false)
{
  amcr::Recognizer recognizer(p, amcr_test::memoryWithApple());
  const cv::Point2d centre = amcr::applyAffine(truth, amcr_test::kAppleCentre);
  const cv::Point2d tip = amcr::applyAffine(truth, amcr_test::kAppleStemTip);
  const auto near = [](const cv::Point2d& a, const cv::Point2d& b) { return std::hypot(a.x - b.x, a.y - b.y) <= 6.0; };
  int reports = 0;
  for (const cv::Mat& frame : frames)
  {
    bool found = false;
    for (const amcr::RecognizedObject& o : recognizer.step(frame).objects)
      found = found || (o.label == "apple" && near(amcr::applyAffine(o.prototype_to_image, amcr_test::kAppleCentre), centre) &&
                        (!upright || near(amcr::applyAffine(o.prototype_to_image, amcr_test::kAppleStemTip), tip)));
    reports += found;
  }
  return reports;
}

amcr::Params params(std::uint64_t seed)
{
  amcr::Params p;
  p.seed = seed;
  return p;
}
}  // namespace

TEST(EndToEndRivals, ARoundBlobIsNotReportedAsAnApple)
{
  int unchecked_total = 0;
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    amcr::Affine truth;
    const std::vector<cv::Mat> disc = appleFrames(false, 400 + seed, truth);
    amcr::Params unchecked = params(seed);
    unchecked.rival_part_support = 0.0;
    const int reports = appleReports(disc, truth, params(seed));
    const int unchecked_reports = appleReports(disc, truth, unchecked);
    unchecked_total += unchecked_reports;
    std::cout << "[ rivals   ] seed " << seed << ": the disc reported as the apple in " << reports << " of " << kFrames
              << " frames (" << unchecked_reports << " without the rival check)" << std::endl;
    EXPECT_EQ(reports, 0) << "seed " << seed << ": a disc was reported as the apple";
  }
  EXPECT_GT(unchecked_total, 0) << "without the rival check the disc was never taken for the apple either: the "
                                   "scene does not test the check";
}

TEST(EndToEndRivals, TheAppleItselfIsReported)
{
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    amcr::Affine truth;
    const std::vector<cv::Mat> apple = appleFrames(true, 400 + seed, truth);
    const int reports = appleReports(apple, truth, params(seed), true);
    std::cout << "[ rivals   ] seed " << seed << ": the apple reported upright in " << reports << " of " << kFrames
              << " frames" << std::endl;
    // Measured: 26, 53 and 21 frames (seeds 1-3); a round body's turn is
    // found from its stem only (rival_check.cpp), in some frames not.
    EXPECT_GE(reports, kFrames / 4) << "seed " << seed << ": the apple itself was not held with its stem in place";
  }
}
