// Partly hidden objects (covered_outline.h): an outline point under
// something in front of the object counts as covered, not missing, so a
// target with a quarter of it behind a flat occluder is found and a held one
// keeps its track while half covered; a shape that is not there is still
// missing (a disc is no apple however much of it is covered), and an
// occluder alone is no object.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/outline_fit.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "amcr/scan/radial_scan.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr double kOccluderGrey = 115.0;   // between the print (about 45) and the paper (about 195)
constexpr double kOccluderNoise = 6.0;    // grey levels, as the scene's
constexpr double kCornerTolerance = 6.0;  // px, mean corner error of a right report (as the end-to-end tests)

amcr::Params params(std::uint64_t seed)
{
  amcr::Params p;
  p.seed = seed;
  return p;
}

/// Where a prototype image (255 on the shape) lies in a frame of `size` under `truth`.
cv::Mat targetMask(const cv::Mat& silhouette, const amcr::Affine& truth, const cv::Size& size)
{
  cv::Mat mask;
  cv::warpAffine(silhouette, mask, cv::Mat(truth), size, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  return mask;
}

/// The rectangle over the share `share` of the mask's area that lies
/// furthest along the direction `angle` (rad), reaching 30 px beyond the
/// mask on its three other sides; empty for an empty mask.
std::vector<cv::Point> occluderOver(const cv::Mat& mask, double angle, double share)
{
  const cv::Point2d along(std::cos(angle), std::sin(angle)), across(-along.y, along.x);
  std::vector<double> t;
  double s_min = 1e9, s_max = -1e9;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x)
      if (mask.at<std::uint8_t>(y, x) > 127)
      {
        t.push_back(x * along.x + y * along.y);
        const double s = x * across.x + y * across.y;
        s_min = std::min(s_min, s);
        s_max = std::max(s_max, s);
      }
  if (t.empty())
    return {};
  std::sort(t.begin(), t.end());
  const double t0 = t[static_cast<std::size_t>((1.0 - share) * static_cast<double>(t.size() - 1))];
  const double t1 = t.back() + 30.0;
  s_min -= 30.0;
  s_max += 30.0;
  std::vector<cv::Point> corners;
  for (const cv::Point2d& ts : {cv::Point2d(t0, s_min), cv::Point2d(t1, s_min), cv::Point2d(t1, s_max),
                                cv::Point2d(t0, s_max)})
    corners.emplace_back(cvRound(ts.x * along.x + ts.y * across.x), cvRound(ts.x * along.y + ts.y * across.y));
  return corners;
}

/// Share of the mask's area under `occluder`.
double coveredArea(const cv::Mat& mask, const std::vector<cv::Point>& occluder)
{
  cv::Mat under = cv::Mat::zeros(mask.size(), CV_8UC1);
  cv::fillConvexPoly(under, occluder, cv::Scalar(255));
  return static_cast<double>(cv::countNonZero(under & (mask > 127))) / std::max(1, cv::countNonZero(mask > 127));
}

/// A flat grey occluder with the scene's noise drawn over `frame`.
void drawOccluder(cv::Mat& frame, const std::vector<cv::Point>& occluder, std::uint64_t seed)
{
  cv::Mat under = cv::Mat::zeros(frame.size(), CV_8UC1);
  cv::fillConvexPoly(under, occluder, cv::Scalar(255));
  const cv::Mat flat = amcr_test::addNoise(cv::Mat(frame.size(), CV_8UC1, cv::Scalar(kOccluderGrey)), kOccluderNoise, seed);
  flat.copyTo(frame, under);
}

/// Frames with a right report (label and pose) of `label` at `truth`.
struct Reports
{
  int right = 0;
  int first_right = -1;
  int loose = 0;           ///< reports of the label with a mean corner error above kCornerTolerance
  double largest = 0.0;    ///< px: the largest mean corner error of a report of the label
  int wrong = 0;           ///< reports of another label
};

Reports run(const std::vector<cv::Mat>& frames, const std::string& label, const amcr::Affine& truth,
            const amcr::Params& p)
{
  amcr::Recognizer recognizer(p, amcr_test::memoryWithApple());
  Reports out;
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    bool right = false;
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      if (o.label != label)
      {
        ++out.wrong;
        continue;
      }
      const double error = amcr_test::cornerError(o.prototype_to_image, truth);
      out.largest = std::max(out.largest, error);
      right = right || error <= kCornerTolerance;
      out.loose += error > kCornerTolerance ? 1 : 0;
    }
    out.right += right;
    if (right && out.first_right < 0)
      out.first_right = static_cast<int>(k);
  }
  return out;
}
}  // namespace

// The verification itself: an apple printed with a quarter of it under a
// flat occluder scores on its visible outline; a disc (the apple without its
// stem) is missing the stem, which no surface covers.
TEST(PartlyHidden, CoveredPointsAreToldFromMissingOnes)
{
  const amcr::Params defaults;
  amcr::PrototypeMemory apple;
  apple.add("apple", amcr_test::drawApple(true), defaults);
  const amcr::Prototype& p = apple[0];
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.3, 0.8, 0.8, 0.0);
  const amcr::Affine table_to_image = amcr::composeAffine(p.tableToOriginal(), truth);
  const cv::Size size(640, 480);
  const auto verify = [&](bool stem, double share, bool find_covered) {
    cv::Mat frame(size, CV_8UC1, cv::Scalar(195));
    const cv::Mat mask = targetMask(amcr_test::drawApple(stem), truth, size);
    frame.setTo(cv::Scalar(45), mask > 127);
    frame = amcr_test::addNoise(frame, kOccluderNoise, 7);
    if (share > 0.0)
      drawOccluder(frame, occluderOver(mask, 0.0, share), 8);  // the right side covered
    const amcr::RadialScanner scanner(amcr::prepareScanImage(frame, defaults.blur_sigma), defaults.edge_threshold,
                                      defaults.max_ray_length);
    return amcr::verifyOutline(p, scanner, table_to_image, 1.5, 0.0, find_covered);
  };
  const amcr::OutlineVerification covered = verify(true, 0.25, true);
  const amcr::OutlineVerification whole = verify(true, 0.25, false);
  std::cout << "[ hidden   ] a quarter covered: visible " << covered.visible_share << ", score " << covered.score
            << " (the whole outline's " << whole.score << ")" << std::endl;
  // A quarter of the area is about a third of the outline, with the stretch
  // along the occluder's contour (covered too: it is the occluder's edge).
  EXPECT_GE(covered.visible_share, 0.55) << "more than the covered part was found covered";
  EXPECT_LE(covered.visible_share, 0.8) << "the covered quarter of the outline was not found covered";
  EXPECT_GE(covered.score, 0.9) << "the visible outline is on its edges";
  EXPECT_LT(whole.score, 0.8) << "without covered points the quarter counts as missing";

  const amcr::OutlineVerification disc = verify(false, 0.0, true);
  std::cout << "[ hidden   ] a disc as the apple: visible " << disc.visible_share << ", score " << disc.score
            << std::endl;
  EXPECT_EQ(disc.visible_share, 1.0) << "the missing stem was taken for a covered one";
  EXPECT_LT(disc.score, 0.9);

  const amcr::OutlineVerification plain = verify(true, 0.0, true);
  EXPECT_EQ(plain.visible_share, 1.0) << "a point of an uncovered apple was found covered";
  EXPECT_GE(plain.score, 0.95);
}

// A drawn target over clutter with a quarter of its area behind a flat grey
// occluder (its right side), in every frame: found, with its pose, by each of
// seeds 1-5, and nothing else reported. Measured: found at frames 4-13; with
// min_visible_share 1 (no point counts as covered) by none in 30 frames.
// The covered side is not seen: its corners may be off by more (a mean
// corner error of up to 13 px in a few frames).
TEST(PartlyHidden, AQuarterCoveredTargetIsFound)
{
  constexpr int kFrames = 30;
  constexpr double kLargestLooseError = 20.0;  // px: a report of the label further off is a wrong pose
  const ShapeId shape = ShapeId::kCrescent;
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 0.4, 0.85, 0.8, 0.1);
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3, 4, 5}, 2))
  {
    std::vector<cv::Mat> frames = amcr_test::printedOverClutter(amcr_test::drawPrototype(shape), truth,
                                                                amcr_test::distractorClutter(500 + seed), kFrames);
    const cv::Mat mask = targetMask(amcr_test::drawPrototype(shape), truth, frames[0].size());
    const std::vector<cv::Point> occluder = occluderOver(mask, 0.0, 0.25);
    ASSERT_NEAR(coveredArea(mask, occluder), 0.25, 0.02) << "the scene does not cover a quarter";
    for (std::size_t k = 0; k < frames.size(); ++k)
      drawOccluder(frames[k], occluder, 900 + k);
    const Reports reports = run(frames, amcr_test::shapeName(shape), truth, params(seed));
    std::cout << "[ hidden   ] seed " << seed << ": a quarter covered, found at frame " << reports.first_right
              << ", right in " << reports.right << " of " << kFrames << " frames (" << reports.loose
              << " more with a corner error up to " << reports.largest << " px), " << reports.wrong
              << " reports of another label" << std::endl;
    EXPECT_GE(reports.first_right, 0) << "seed " << seed << ": the quarter-covered crescent was not found";
    EXPECT_EQ(reports.wrong, 0) << "seed " << seed;
    EXPECT_LE(reports.largest, kLargestLooseError) << "seed " << seed;
  }
}

// A disc half covered, the stem's side behind the occluder, is not an apple:
// too little of it shows, and what shows does not tell it from a round blob.
TEST(PartlyHidden, AHalfCoveredDiscIsNotAnApple)
{
  constexpr int kFrames = 30;
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {300, 250}, 0.3, 0.8, 0.8, 0.0);
  const auto apples = [&](const std::vector<cv::Mat>& frames, const amcr::Params& p) {
    amcr::Recognizer recognizer(p, amcr_test::memoryWithApple());
    int count = 0;
    for (const cv::Mat& frame : frames)
      for (const amcr::RecognizedObject& o : recognizer.step(frame).objects)
        count += o.label == "apple";
    return count;
  };
  int unchecked_total = 0;
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    for (const double share : {0.5, 0.3})
    {
      std::vector<cv::Mat> frames =
          amcr_test::printedOverClutter(amcr_test::drawApple(false), truth, amcr_test::distractorClutter(400 + seed), kFrames);
      const cv::Mat mask = targetMask(amcr_test::drawApple(false), truth, frames[0].size());
      // Up in the apple's frame, where its stem would be: the turn 0.3 rad moves it.
      const std::vector<cv::Point> occluder = occluderOver(mask, -M_PI / 2 + 0.3, share);
      for (std::size_t k = 0; k < frames.size(); ++k)
        drawOccluder(frames[k], occluder, 900 + k);
      // The control: nothing checks what shows, any share of it may be covered.
      amcr::Params unchecked = params(seed);
      unchecked.rival_part_support = 0.0;
      unchecked.min_visible_share = 0.0;
      const int reports = apples(frames, params(seed));
      const int unchecked_reports = apples(frames, unchecked);
      unchecked_total += unchecked_reports;
      std::cout << "[ hidden   ] seed " << seed << ": a disc " << share * 100 << " % covered reported as the apple in "
                << reports << " of " << kFrames << " frames (" << unchecked_reports
                << " without the rival check and the visible share)" << std::endl;
      EXPECT_EQ(reports, 0) << "seed " << seed << ": a disc " << share * 100 << " % covered was taken for the apple";
    }
  }
  EXPECT_GT(unchecked_total, 0) << "without the checks the covered disc was never taken for the apple either: the "
                                   "scene does not test them";
}

// An occluder alone, flat or striped, over clutter: no object.
TEST(PartlyHidden, AnOccluderAloneIsNoObject)
{
  constexpr int kFrames = 30;
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    amcr_test::Scene scene;
    scene.clutter = amcr_test::distractorClutter(600 + seed);
    std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, kFrames);
    const std::vector<cv::Point> flat = {{120, 140}, {300, 110}, {330, 260}, {150, 300}};
    const std::vector<cv::Point> striped = {{380, 260}, {560, 250}, {570, 420}, {390, 430}};
    for (std::size_t k = 0; k < frames.size(); ++k)
    {
      drawOccluder(frames[k], flat, 900 + k);
      cv::Mat stripes(frames[k].size(), CV_8UC1, cv::Scalar(90));
      for (int x = 0; x < stripes.cols; x += 16)
        cv::rectangle(stripes, cv::Rect(x, 0, 8, stripes.rows), cv::Scalar(150), cv::FILLED);
      cv::Mat under = cv::Mat::zeros(frames[k].size(), CV_8UC1);
      cv::fillConvexPoly(under, striped, cv::Scalar(255));
      stripes.copyTo(frames[k], under);
    }
    amcr::Recognizer recognizer(params(seed), amcr_test::memoryWithApple());
    int reports = 0;
    for (const cv::Mat& frame : frames)
      reports += static_cast<int>(recognizer.step(frame).objects.size());
    std::cout << "[ hidden   ] seed " << seed << ": occluders alone, " << reports << " reports in " << kFrames
              << " frames" << std::endl;
    EXPECT_EQ(reports, 0) << "seed " << seed << ": an occluder was reported as an object";
  }
}

// A held object moving over clutter keeps its track id while the half of it
// furthest along one direction is covered for 20 frames, the occluder going
// with it, and after.
TEST(PartlyHidden, AHeldObjectKeepsItsTrackWhileHalfCovered)
{
  constexpr int kFound = 30, kCovered = 20, kAfter = 10;
  const auto poseAt = [](int k) {
    return amcr_test::makeAffine(amcr_test::prototypeCentre(), {280.0 + 1.0 * k, 240.0 + 0.5 * k}, 0.2 + 0.01 * k,
                                 0.85, 0.8, 0.0);
  };
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    amcr_test::Scene scene;
    scene.clutter = amcr_test::distractorClutter(700 + seed);
    scene.objects = {{ShapeId::kArrow, poseAt(0)}};
    std::vector<cv::Mat> frames = amcr_test::renderMovingSequence(
        scene, kFound + kCovered + kAfter, [&](int k) { return std::vector<amcr_test::Placement>{{ShapeId::kArrow, poseAt(k)}}; });
    for (int k = kFound; k < kFound + kCovered; ++k)
    {
      const cv::Mat mask = targetMask(amcr_test::drawPrototype(ShapeId::kArrow), poseAt(k), frames[k].size());
      drawOccluder(frames[k], occluderOver(mask, 0.5 * seed, 0.5), 900 + k);
    }
    amcr::Recognizer recognizer(params(seed), amcr_test::memoryWithApple());
    int id_before = 0, covered_reports = 0, after_reports = 0;
    std::set<int> ids_covered, ids_after;
    double least_visible = 1.0;
    for (int k = 0; k < static_cast<int>(frames.size()); ++k)
    {
      const amcr::RecognitionResult result = recognizer.step(frames[k]);
      for (const amcr::RecognizedObject& o : result.objects)
      {
        if (o.label != "arrow" || amcr_test::cornerError(o.prototype_to_image, poseAt(k)) > 2 * kCornerTolerance)
          continue;
        if (k < kFound)
          id_before = o.track_id;
        else if (k < kFound + kCovered)
        {
          ++covered_reports;
          ids_covered.insert(o.track_id);
          least_visible = std::min(least_visible, o.visible_share);
        }
        else
        {
          ++after_reports;
          ids_after.insert(o.track_id);
        }
      }
    }
    std::cout << "[ hidden   ] seed " << seed << ": track " << id_before << " before; half covered, reported in "
              << covered_reports << " of " << kCovered << " frames (least visible share " << least_visible
              << "); after, in " << after_reports << " of " << kAfter << std::endl;
    ASSERT_NE(id_before, 0) << "seed " << seed << ": the arrow was not found before the occluder came";
    EXPECT_EQ(covered_reports, kCovered) << "seed " << seed << ": the half-covered arrow was dropped";
    EXPECT_EQ(ids_covered, std::set<int>{id_before}) << "seed " << seed << ": the track id changed under the occluder";
    EXPECT_LT(least_visible, 0.75) << "seed " << seed << ": the covered half was not reported as covered";
    EXPECT_GE(after_reports, kAfter - 1) << "seed " << seed;
    EXPECT_EQ(ids_after, std::set<int>{id_before}) << "seed " << seed << ": the track id changed after the occluder";
  }
}
