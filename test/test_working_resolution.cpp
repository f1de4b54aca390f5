// Resolution independence (the filter works on the input reduced to
// working_resolution, so a larger frame of a scene is recognized as the
// smaller one and costs no more): the same drawn scene at
// 640x480 and twice as large (1280x960) is recognized within the same
// iterations, the larger one with corners within twice the tolerance, in
// input px; working_resolution 0, and an input not larger than
// working_resolution, leave the recognizer as it was (bit for bit).
#include <cmath>
#include <iostream>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/recognizer.h"
#include "amcr/working_scale.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kMaxIterations = 100;       // as test_recognition_end_to_end.cpp
constexpr double kCornerTolerance = 6.0;  // px at 640x480; times the scale at a larger input

std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m =
      amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar});
  return m;
}

amcr::Params params(int working_resolution)
{
  amcr::Params p;
  p.seed = 1;
  p.working_resolution = working_resolution;
  return p;
}

// The arrow of the end-to-end case arrow_101 (120-150 px across) over clutter, at 640x480.
std::vector<cv::Mat> arrowScene(amcr::Affine& truth, int frames)
{
  truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 35 * M_PI / 180, 0.85, 0.75, 0.25);
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kArrow, truth});
  scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  scene.clutter.seed = 101;
  return amcr_test::renderSequence(scene, frames);
}

// `frames` enlarged by `factor` (bilinear, as a camera of that resolution
// would show the scene, blur and all); `truth` follows (pixel centres:
// x' = factor x + (factor - 1) / 2).
std::vector<cv::Mat> enlarged(const std::vector<cv::Mat>& frames, int factor, amcr::Affine& truth)
{
  const double offset = 0.5 * (factor - 1);
  truth = amcr::composeAffine(truth, amcr::Affine(factor, 0, offset, 0, factor, offset));
  std::vector<cv::Mat> out;
  for (const cv::Mat& f : frames)
  {
    cv::Mat big;
    cv::resize(f, big, f.size() * factor, 0, 0, cv::INTER_LINEAR);
    out.push_back(big);
  }
  return out;
}

// First iteration (1-based) at which the arrow is reported within `tolerance`; -1: never.
int firstCorrect(amcr::Recognizer& recognizer, const std::vector<cv::Mat>& frames, const amcr::Affine& truth,
                 double tolerance, double& error)
{
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      error = amcr_test::cornerError(o.prototype_to_image, truth);
      if (o.label == "arrow" && error <= tolerance)
        return static_cast<int>(k) + 1;
    }
  return -1;
}

TEST(WorkingResolution, TheSameSceneTwiceAsLargeIsRecognizedInInputPixels)
{
  amcr::Affine truth;
  const std::vector<cv::Mat> small = arrowScene(truth, kMaxIterations);
  amcr::Affine big_truth = truth;
  const std::vector<cv::Mat> big = enlarged(small, 2, big_truth);
  ASSERT_EQ(big[0].size(), cv::Size(1280, 960));

  double small_error = -1, big_error = -1;
  amcr::Recognizer at_640(params(640), memory());
  const int small_first = firstCorrect(at_640, small, truth, kCornerTolerance, small_error);
  amcr::Recognizer at_1280(params(640), memory());
  const int big_first = firstCorrect(at_1280, big, big_truth, 2 * kCornerTolerance, big_error);
  std::cout << "[ scale    ] 640x480: first correct at iteration " << small_first << " (corner error " << small_error
            << " px); 1280x960: " << big_first << " (" << big_error << " px)" << std::endl;
  EXPECT_GT(small_first, 0) << "640x480: never recognized within " << kMaxIterations << " iterations";
  EXPECT_GT(big_first, 0) << "1280x960: never recognized within " << kMaxIterations << " iterations";

  // The filter worked at 640x480; what it shows is in input px.
  const amcr::WorkingScale& scale = at_1280.workingScale();
  EXPECT_EQ(scale.working, cv::Size(640, 480));
  const amcr::FilterView view = at_1280.view();
  ASSERT_EQ(view.v.size(), at_1280.vParticles().size());
  for (std::size_t i = 0; i < view.v.size(); ++i)
  {
    const amcr::VParticle& v = at_1280.vParticles()[i];
    EXPECT_FLOAT_EQ(view.v[i].position.x, 2 * v.x + 0.5f);
    EXPECT_FLOAT_EQ(view.v[i].position.y, 2 * v.y + 0.5f);
  }
  // Displacements come in input px: 4 input px are 2 working px.
  const std::vector<amcr::VParticle> before = at_1280.vParticles();
  at_1280.moveVParticles(std::vector<cv::Point2f>(before.size(), cv::Point2f(4.f, -4.f)));
  for (std::size_t i = 0; i < before.size(); ++i)
  {
    EXPECT_FLOAT_EQ(at_1280.vParticles()[i].x, std::min(before[i].x + 2.f, 639.f));
    EXPECT_FLOAT_EQ(at_1280.vParticles()[i].y, std::max(before[i].y - 2.f, 0.f));
  }
}

void expectSameResult(const amcr::RecognitionResult& a, const amcr::RecognitionResult& b, const std::string& what)
{
  EXPECT_EQ(a.iteration, b.iteration) << what;
  EXPECT_EQ(a.flow_failures, b.flow_failures) << what;
  EXPECT_EQ(a.converged_v_particles, b.converged_v_particles) << what;
  ASSERT_EQ(a.objects.size(), b.objects.size()) << what;
  for (std::size_t i = 0; i < a.objects.size(); ++i)
  {
    const amcr::RecognizedObject& x = a.objects[i];
    const amcr::RecognizedObject& y = b.objects[i];
    EXPECT_EQ(x.label, y.label) << what;
    EXPECT_EQ(x.track_id, y.track_id) << what;
    EXPECT_EQ(x.score, y.score) << what;
    EXPECT_EQ(x.support, y.support) << what;
    EXPECT_EQ(x.prototype_to_image, y.prototype_to_image) << what;
    EXPECT_EQ(x.image_to_prototype, y.image_to_prototype) << what;
    EXPECT_EQ(x.homography, y.homography) << what;
    EXPECT_EQ(x.homography_valid, y.homography_valid) << what;
    EXPECT_EQ(x.anisotropy, y.anisotropy) << what;
    EXPECT_EQ(x.outline, y.outline) << what;
    ASSERT_EQ(x.correspondences.size(), y.correspondences.size()) << what;
    for (std::size_t j = 0; j < x.correspondences.size(); ++j)
    {
      EXPECT_EQ(x.correspondences[j].image, y.correspondences[j].image) << what;
      EXPECT_EQ(x.correspondences[j].prototype, y.correspondences[j].prototype) << what;
    }
  }
}

// Equal V-particles (bit for bit) and equal results in every frame.
void expectSameRun(const std::vector<cv::Mat>& frames, int resolution_a, int resolution_b, bool reports = true)
{
  amcr::Recognizer a(params(resolution_a), memory());
  amcr::Recognizer b(params(resolution_b), memory());
  int reported = 0;
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    const std::string what = "frame " + std::to_string(k) + " of " + std::to_string(frames[k].cols) + "x" +
                             std::to_string(frames[k].rows) + ", working_resolution " + std::to_string(resolution_a) +
                             " vs " + std::to_string(resolution_b);
    const amcr::RecognitionResult ra = a.step(frames[k]);
    const amcr::RecognitionResult rb = b.step(frames[k]);
    reported += !ra.objects.empty();
    expectSameResult(ra, rb, what);
    ASSERT_EQ(a.vParticles().size(), b.vParticles().size());
    for (std::size_t i = 0; i < a.vParticles().size(); ++i)
    {
      ASSERT_EQ(a.vParticles()[i].x, b.vParticles()[i].x) << what;
      ASSERT_EQ(a.vParticles()[i].y, b.vParticles()[i].y) << what;
    }
    ASSERT_EQ(a.view().v.size(), b.view().v.size());
  }
  if (reports)
  {
    EXPECT_GT(reported, 0) << "nothing was reported: the comparison covered no objects";
  }
}

// 0 is the input's own size; 640 and 4000 do not reduce a 640x480 input, and
// 640 does not enlarge a 320x240 one: all run exactly as without the option.
TEST(WorkingResolution, AnInputNotLargerIsUntouched)
{
  amcr::Affine truth;
  // 40 frames (20 under the sanitizers, test/run_length.h): the arrow is reported from frame 5.
  const std::vector<cv::Mat> frames = arrowScene(truth, amcr_test::runLength(40, 20));
  expectSameRun(frames, 0, 640);
  expectSameRun(frames, 0, 4000);
  std::vector<cv::Mat> small;
  for (const cv::Mat& f : frames)
  {
    cv::Mat half;
    cv::resize(f, half, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    small.push_back(half);
  }
  expectSameRun(small, 0, 640, false);  // an arrow of 60-75 px: below min_object_size, nothing reported
  amcr::Recognizer r(params(640), memory());
  r.step(small[0]);
  EXPECT_TRUE(r.workingScale().identity());
  EXPECT_EQ(r.workingScale().working, cv::Size(320, 240));
}
}  // namespace
