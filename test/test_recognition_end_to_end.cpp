// End to end, with inputs drawn in code: three distinct
// prototypes in memory; a sequence showing one of them under a known affine
// (rotation, anisotropic scale, shear) over clutter (other shapes, other
// silhouettes, lines, a brightness gradient, noise). Within a bounded number
// of iterations the right label must be reported with prototype_to_image
// mapping the prototype's corners near the truth; on clutter alone nothing
// may be reported.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/outline_fit.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

// Bounds of the test.
// Iterations to a correct report. Measured over these six scenes with
// recognizer seeds 1-3 (noisy frames, defaults): median 20, all 18 within
// 100; with one seed a scene may take up to 58.
constexpr int kMaxIterations = 100;
constexpr double kCornerTolerance = 6.0;  // px, mean corner error of prototype_to_image
// Once recognized, a static object must stay recognized (within the corner
// tolerance) in at least this share of the remaining iterations.
constexpr double kMinHoldShare = 0.5;

// The memory: three silhouettes; the other two drawn shapes (ell, flag) are
// clutter the recognizer has never seen.
const std::vector<ShapeId> kMemory = {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar};

// Built once: the memory is immutable and its tables take a while to build.
std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m = amcr_test::drawnMemory(kMemory);
  return m;
}

amcr::Params params()
{
  amcr::Params p;  // defaults: 30 V x 60 M per prototype per V (the paper's video experiment)
  p.seed = 1;
  return p;
}

amcr_test::Clutter clutter(std::uint64_t seed)
{
  amcr_test::Clutter c;
  c.random_shapes = 7;
  c.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  c.lines = 10;
  c.noise_sigma = 6.0;
  c.gradient = 60.0;
  c.seed = seed;
  return c;
}

struct Target
{
  ShapeId shape;
  cv::Point2d centre;  // image px
  double rotation;     // rad
  double scale_x, scale_y, shear;
  std::uint64_t clutter_seed;
};

void PrintTo(const Target& t, std::ostream* os)
{
  *os << amcr_test::shapeName(t.shape) << " clutter seed " << t.clutter_seed;
}

class EndToEnd : public ::testing::TestWithParam<Target>
{
};

// The target of a case over its clutter, for kMaxIterations frames; `truth` is its prototype->image affine.
std::vector<cv::Mat> renderTarget(const Target& t, amcr::Affine& truth)
{
  truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), t.centre, t.rotation, t.scale_x, t.scale_y, t.shear);
  amcr_test::Scene scene;
  scene.objects.push_back({t.shape, truth});
  scene.clutter = clutter(t.clutter_seed);
  return amcr_test::renderSequence(scene, kMaxIterations);
}

// An arrow 120-150 px across (case arrow_101).
const Target kArrow101{ShapeId::kArrow, {330, 250}, 35 * M_PI / 180, 0.85, 0.75, 0.25, 101};

TEST_P(EndToEnd, RecognizesTheShapeAndItsAffine)
{
  const Target t = GetParam();
  const std::string label = amcr_test::shapeName(t.shape);
  amcr::Affine truth;
  const std::vector<cv::Mat> frames = renderTarget(t, truth);

  amcr::Recognizer recognizer(params(), memory());
  int first_correct = -1;  // first iteration (1-based) reporting the label within the corner tolerance
  int held = 0;            // iterations from first_correct on that report it within the tolerance
  int wrong_reports = 0;   // objects of another label, over all iterations
  int off_reports = 0;     // reports of the right label farther than the tolerance
  std::vector<double> errors;  // corner errors of the right label's reports
  for (int k = 0; k < kMaxIterations; ++k)
  {
    const amcr::RecognitionResult result = recognizer.step(frames[k]);
    bool correct = false;
    for (const amcr::RecognizedObject& o : result.objects)
    {
      if (o.label != label)
      {
        ++wrong_reports;
        continue;
      }
      const double e = amcr_test::cornerError(o.prototype_to_image, truth);
      errors.push_back(e);
      correct = correct || e <= kCornerTolerance;
      off_reports += e > kCornerTolerance;
    }
    if (correct && first_correct < 0)
      first_correct = k + 1;
    if (first_correct > 0)
      held += correct;
  }
  const int since = first_correct > 0 ? kMaxIterations - first_correct + 1 : 0;
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  std::ostringstream summary;
  summary << label << " (clutter seed " << t.clutter_seed << "): first correct at iteration " << first_correct
          << ", held in " << held << " of " << since << " iterations since; " << errors.size() << " reports of "
          << label << " (median corner error " << (sorted.empty() ? -1.0 : sorted[sorted.size() / 2]) << " px, "
          << off_reports << " beyond " << kCornerTolerance << " px), " << wrong_reports << " of other labels";
  std::cout << "[ e2e      ] " << summary.str() << std::endl;
  RecordProperty("first_correct_iteration", first_correct);
  RecordProperty("held", held);
  RecordProperty("wrong_reports", wrong_reports);

  ASSERT_GT(first_correct, 0) << label << " never reported within " << kCornerTolerance << " px in "
                              << kMaxIterations << " iterations: " << summary.str();
  EXPECT_GE(held, kMinHoldShare * since) << "recognized, then lost: " << summary.str();
  EXPECT_EQ(wrong_reports, 0) << "objects of another label were reported: " << summary.str();
}

// Rotation, anisotropic scale and shear differ per case; the objects are
// 120-170 px across (prototype images 200 px, shapes ~170 px). Two scenes
// per target, so one lucky run does not decide (under the sanitizers the
// first scene of each: test/run_length.h).
INSTANTIATE_TEST_SUITE_P(
    ThreePrototypes, EndToEnd,
    ::testing::ValuesIn(amcr_test::firstOf<Target>(
        {kArrow101, Target{ShapeId::kCrescent, {300, 230}, -50 * M_PI / 180, 0.9, 1.0, -0.2, 102},
         Target{ShapeId::kStar, {340, 240}, 110 * M_PI / 180, 0.8, 0.9, 0.15, 103},
         Target{ShapeId::kArrow, {300, 220}, -120 * M_PI / 180, 0.95, 0.8, -0.15, 104},
         Target{ShapeId::kCrescent, {350, 260}, 150 * M_PI / 180, 0.8, 0.9, 0.25, 105},
         Target{ShapeId::kStar, {290, 250}, -20 * M_PI / 180, 0.95, 0.85, -0.2, 106}},
        3)),
    [](const ::testing::TestParamInfo<Target>& info) {
      return amcr_test::shapeName(info.param.shape) + "_" + std::to_string(info.param.clutter_seed);
    });

// Oblique views: anisotropy 2.5, i.e. the print seen 66 degrees
// off its normal (scale sqrt(2.5) times s along one axis, s / sqrt(2.5)
// across it, s = 0.85), rotated, over the same clutter; the same bounds.
// Measured with recognizer seeds 1-4 and the defaults (a budget of
// M-particles, half of the new ones from the proposal index): crescent_202
// in 4 of 4 runs (iterations 21-87; 7-31 with the paper's fixed count per
// prototype and no index). Not here because they fail: arrow_201 (25 deg)
// was found in 1 of 4 runs (iteration 22; 3 of 4 without the index: it
// proposes frontal view shapes, so a quarter of the new M-particles, not
// half, start oblique); the star at anisotropy 2.5 (scene 203, 140 deg) in
// none of 4 runs without the index either: its thin
// points, squashed, leave few rays that meet the same edges in the image and
// in the table (docs/how-it-works.md, "Oblique views: affine-corrected scans").
Target oblique(ShapeId shape, cv::Point2d centre, double rotation_deg, std::uint64_t clutter_seed)
{
  const double s = 0.85, stretch = std::sqrt(2.5);
  return Target{shape, centre, rotation_deg * M_PI / 180, s * stretch, s / stretch, 0.0, clutter_seed};
}

INSTANTIATE_TEST_SUITE_P(
    ObliqueViews, EndToEnd,
    ::testing::Values(oblique(ShapeId::kCrescent, {310, 250}, -70, 202)),
    [](const ::testing::TestParamInfo<Target>& info) {
      return amcr_test::shapeName(info.param.shape) + "_" + std::to_string(info.param.clutter_seed);
    });

// The views a new object is reported at are bounded by max_anisotropy (the
// filter proposes none beyond; past it an affine stretches a simple outline
// onto elongated blobs: clutter-only scenes showed a rounded triangle
// reported on a dark wedge at anisotropy 3.5 and 4.7). The oblique crescent
// above (anisotropy 2.5) is reported with the default bound of 3; with a
// bound of 2 it is never reported. Measured without the rule, bound 2:
// reported in 89 of 100 frames (the filter still finds it through the
// index's frontal proposals).
TEST(EndToEndViewBound, AViewBeyondMaxAnisotropyIsNotReportedAsNew)
{
  const Target t = oblique(ShapeId::kCrescent, {310, 250}, -70, 202);
  amcr::Affine truth;
  const std::vector<cv::Mat> frames = renderTarget(t, truth);
  // Frames with the crescent reported under a bound on the views.
  const auto reportedFrames = [&frames](double max_anisotropy) {
    amcr::Params p = params();
    p.max_anisotropy = max_anisotropy;
    amcr::Recognizer recognizer(p, memory());
    int reports = 0;
    for (int k = 0; k < kMaxIterations; ++k)
      for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
        reports += o.label == "crescent" ? 1 : 0;
    return reports;
  };
  const int within = reportedFrames(3.0), beyond = reportedFrames(2.0);
  std::cout << "[ views    ] the crescent at anisotropy 2.5: reported in " << within << " of " << kMaxIterations
            << " frames under a bound of 3, " << beyond << " under a bound of 2\n";
  EXPECT_GT(within, 0) << "the scene's crescent is not found even within the bound: the test shows nothing";
  EXPECT_EQ(beyond, 0);
}

// min_object_size: the same arrow scene, recognized (right label, corners
// within the tolerance) when any size is reported, gives no report at all
// when the smallest reported size is larger than the arrow.
TEST(EndToEndSize, ObjectsSmallerThanTheMinimumAreNotReported)
{
  amcr::Affine truth;
  const std::vector<cv::Mat> frames = renderTarget(kArrow101, truth);
  const std::string label = amcr_test::shapeName(kArrow101.shape);
  for (const double min_size : {0.0, 250.0})
  {
    amcr::Params p = params();
    p.min_object_size = min_size;
    amcr::Recognizer recognizer(p, memory());
    int reports = 0, correct = 0;
    double largest = 0.0;
    // Without a bound one right report decides; with it every iteration must be silent.
    const bool until_correct = min_size == 0.0;
    for (int k = 0; k < kMaxIterations && !(until_correct && correct > 0); ++k)
      for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
      {
        ++reports;
        largest = std::max(largest, amcr::outlineSize(o.outline));
        correct += o.label == label && amcr_test::cornerError(o.prototype_to_image, truth) <= kCornerTolerance;
      }
    if (min_size == 0.0)
      EXPECT_GT(correct, 0) << "with min_object_size 0 the " << label << " was never reported within "
                            << kCornerTolerance << " px (" << reports << " reports)";
    else
      EXPECT_EQ(reports, 0) << "objects below min_object_size " << min_size << " px were reported (largest "
                            << largest << " px)";
  }
}

// A faint, defocused print (what a dim room and a soft lens give): the arrow
// scene at a quarter of its contrast (the arrow 40 grey levels off the
// paper), blurred by 2 px, with fresh noise of 3 grey levels. Its outline
// steps by at most 14 grey levels over 2 px, so the absolute edge_threshold
// (40) sees none of it; thresholds relative to the local edge strength
// (edge_full_strength, edge_thresholds.h) must find the arrow within the
// same bounds as the sharp scene.
std::vector<cv::Mat> faintAndDefocused(const std::vector<cv::Mat>& frames)
{
  constexpr double kContrast = 0.25, kBlurSigma = 2.0, kNoiseSigma = 3.0;
  std::vector<cv::Mat> out;
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    cv::Mat faint;
    frames[k].convertTo(faint, CV_32F, kContrast, 128.0 * (1.0 - kContrast));
    cv::GaussianBlur(faint, faint, cv::Size(0, 0), kBlurSigma);
    faint.convertTo(faint, CV_8U);
    out.push_back(amcr_test::addNoise(faint, kNoiseSigma, 500 + k));
  }
  return out;
}

// The first iteration that reports `label` within the corner tolerance of
// `truth` (-1: none), and the reports of other labels.
int firstCorrect(amcr::Recognizer& recognizer, const std::vector<cv::Mat>& frames, const std::string& label,
                 const amcr::Affine& truth, int& wrong_reports)
{
  int first_correct = -1;
  wrong_reports = 0;
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      wrong_reports += o.label != label;
      if (first_correct < 0 && o.label == label && amcr_test::cornerError(o.prototype_to_image, truth) <= kCornerTolerance)
        first_correct = static_cast<int>(k) + 1;
    }
  return first_correct;
}

TEST(EndToEndLowContrast, AFaintDefocusedPrintIsRecognized)
{
  amcr::Affine truth;
  const std::vector<cv::Mat> frames = faintAndDefocused(renderTarget(kArrow101, truth));
  const std::string label = amcr_test::shapeName(kArrow101.shape);
  // Relative thresholds (the default): found with every recognizer seed (1-3; 1 under the sanitizers).
  for (const std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    amcr::Params p = params();
    p.seed = seed;
    amcr::Recognizer recognizer(p, memory());
    int wrong_reports = 0;
    const int first_correct = firstCorrect(recognizer, frames, label, truth, wrong_reports);
    std::cout << "[ e2e      ] faint, defocused " << label << ", seed " << seed << ": first correct at iteration "
              << first_correct << ", " << wrong_reports << " reports of other labels" << std::endl;
    EXPECT_GT(first_correct, 0) << "seed " << seed << ": the faint " << label << " was never reported within "
                                << kCornerTolerance << " px in " << kMaxIterations << " iterations";
    EXPECT_EQ(wrong_reports, 0) << "seed " << seed;
  }
  // The absolute threshold everywhere: the outline is not an edge, nothing is found.
  amcr::Params absolute = params();
  absolute.edge_full_strength = 0.0;
  amcr::Recognizer recognizer(absolute, memory());
  int wrong_reports = 0;
  EXPECT_LT(firstCorrect(recognizer, frames, label, truth, wrong_reports), 0)
      << "the absolute threshold found the faint outline: the scene does not test the relative thresholds";
}

/// The sharp scenes of two targets (the arrow and the star of the cases
/// above) are recognized with `p`, within the corner tolerance and with no
/// report of another label; `what` names the setting in the log.
void expectSharpTargetsRecognized(const amcr::Params& p, const std::string& what)
{
  for (const Target& t : {kArrow101, Target{ShapeId::kStar, {340, 240}, 110 * M_PI / 180, 0.8, 0.9, 0.15, 103}})
  {
    amcr::Affine truth;
    const std::vector<cv::Mat> frames = renderTarget(t, truth);
    amcr::Recognizer recognizer(p, memory());
    int wrong_reports = 0;
    const std::string label = amcr_test::shapeName(t.shape);
    const int first_correct = firstCorrect(recognizer, frames, label, truth, wrong_reports);
    std::cout << "[ e2e      ] " << what << ", " << label << ": first correct at iteration " << first_correct << ", "
              << wrong_reports << " reports of other labels" << std::endl;
    EXPECT_GT(first_correct, 0) << what << ": " << label << " never reported within " << kCornerTolerance << " px";
    EXPECT_EQ(wrong_reports, 0) << what << ": " << label;
  }
}

// The frontal candidates from the radial-profile index (profile_index: 1):
// the sharp scenes of two targets are recognized as within the same bounds.
TEST(EndToEndProfileIndex, RecognizesWithProposalsFromTheRadialProfile)
{
  amcr::Params p = params();
  p.profile_index = true;
  expectSharpTargetsRecognized(p, "profile index");
}

// The normalised mixture form of eq. 5 (likelihood_form: mixture): the
// sharp scenes of two targets are recognized within the same bounds. Before
// its invalid rays were weighed as densities too, it recognized nothing.
TEST(EndToEndMixtureForm, RecognizesTheDrawnTargets)
{
  amcr::Params p = params();
  p.likelihood_form = amcr::LikelihoodForm::kMixture;
  expectSharpTargetsRecognized(p, "mixture form");
}

// A look-alike: an oval prototype joins the three, and over clutter a 96 px
// blob follows the oval within 1.8 px all round without being it. With the
// score's tolerance relative to the object's size (the default: 1 px at this
// size) it is never reported; with 2 px at every size
// (verify_relative_tolerance 0) it is, so the scene does test the tolerance.
// The oval itself at the same size is found with the default.
std::shared_ptr<const amcr::PrototypeMemory> memoryWithOval()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m = [] {
    auto memory = std::make_shared<amcr::PrototypeMemory>();
    for (const ShapeId id : kMemory)
      memory->add(amcr_test::shapeName(id), amcr_test::drawPrototype(id), amcr::Params());
    cv::Mat oval(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(0));
    amcr_test::fillPolygon(oval, amcr_test::wavyOval(amcr_test::prototypeCentre(), 80, 50, 0.0), 255);
    memory->add("oval", oval, amcr::Params());
    return memory;
  }();
  return m;
}

/// kMaxIterations frames of clutter with the oval (`wave` 0) or a look-alike
/// waving by `wave` prototype px (0.6 of it in the image), 96 px long, at `truth`.
std::vector<cv::Mat> ovalFrames(double wave, std::uint64_t seed, amcr::Affine& truth)
{
  truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 0.4, 0.6, 0.6, 0.0);
  amcr_test::Scene scene;
  scene.clutter = clutter(seed);
  scene.objects = {{ShapeId::kCrescent, truth}};  // only to keep the clutter off the oval's place
  cv::Mat clean = amcr_test::renderBackground(scene);
  amcr_test::fillPolygon(
      clean, amcr_test::transformPoints(truth, amcr_test::wavyOval(amcr_test::prototypeCentre(), 80, 50, wave)), 35.0);
  std::vector<cv::Mat> frames;
  for (int k = 0; k < kMaxIterations; ++k)
    frames.push_back(amcr_test::addNoise(clean, scene.clutter.noise_sigma, seed * 1000 + static_cast<std::uint64_t>(k)));
  return frames;
}

/// Iterations in which "oval" is reported with its centre within 4 px of
/// the truth's (the oval is symmetric: its corners may be turned half round).
int ovalReports(const std::vector<cv::Mat>& frames, const amcr::Affine& truth, const amcr::Params& p)
{
  amcr::Recognizer recognizer(p, memoryWithOval());
  const cv::Point2d centre = amcr::applyAffine(truth, amcr_test::prototypeCentre());
  int reports = 0;
  for (const cv::Mat& frame : frames)
    for (const amcr::RecognizedObject& o : recognizer.step(frame).objects)
    {
      const cv::Point2d at = amcr::applyAffine(o.prototype_to_image, amcr_test::prototypeCentre());
      reports += o.label == "oval" && std::hypot(at.x - centre.x, at.y - centre.y) <= 4.0;
    }
  return reports;
}

TEST(EndToEndLookAlike, ASmallLookAlikeIsNotReportedWhereTheShapeItselfIs)
{
  amcr::Affine truth;
  const std::vector<cv::Mat> look_alike = ovalFrames(3.0, 301, truth);
  const std::vector<cv::Mat> oval = ovalFrames(0.0, 301, truth);
  amcr::Params fixed = params();
  fixed.verify_relative_tolerance = 0.0;
  const int look_alike_reports = ovalReports(look_alike, truth, params());
  const int look_alike_reports_fixed = ovalReports(look_alike, truth, fixed);
  const int oval_reports = ovalReports(oval, truth, params());
  std::cout << "[ e2e      ] look-alike of the oval reported in " << look_alike_reports << " iterations ("
            << look_alike_reports_fixed << " with 2 px at every size); the oval itself in " << oval_reports << " of "
            << kMaxIterations << std::endl;
  EXPECT_EQ(look_alike_reports, 0) << "the 96 px look-alike was reported as the oval";
  EXPECT_GT(look_alike_reports_fixed, 0) << "not even the fixed 2 px reported the look-alike: the scene does not test "
                                            "the tolerance";
  EXPECT_GE(oval_reports, kMaxIterations / 2) << "the oval itself, at the same size, was not held";
}

// Clutter only: random shapes, the two silhouettes that are not in memory,
// lines, gradient, noise. Nothing may be reported (two scenes; the first
// under the sanitizers: test/run_length.h).
TEST(EndToEndClutter, NothingIsReported)
{
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({201, 202}, 1))
  {
    amcr_test::Scene scene;
    scene.clutter = clutter(seed);
    scene.clutter.random_shapes = 10;
    const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, kMaxIterations);
    amcr::Recognizer recognizer(params(), memory());
    int reports = 0, frames_with_reports = 0;
    std::string first;
    for (int k = 0; k < kMaxIterations; ++k)
    {
      const amcr::RecognitionResult result = recognizer.step(frames[k]);
      reports += static_cast<int>(result.objects.size());
      frames_with_reports += !result.objects.empty();
      if (first.empty() && !result.objects.empty())
        first = "iteration " + std::to_string(k + 1) + ": " + result.objects[0].label + " score " +
                std::to_string(result.objects[0].score) + " support " + std::to_string(result.objects[0].support);
    }
    std::cout << "[ e2e      ] clutter seed " << seed << ": " << reports << " reports in " << frames_with_reports
              << " of " << kMaxIterations << " iterations" << (first.empty() ? "" : "; first at " + first) << std::endl;
    EXPECT_EQ(reports, 0) << "clutter seed " << seed << ": false positives, first at " << first;
  }
}
}  // namespace
