// A camera without noise must do as well as a noisy one: the same drawn
// scene of two large shapes over clutter, once without pixel noise and once with
// the benchmark renderer's, must give the same objects by frame 30. (A
// V-particle on an untextured surface has no optical flow of its own; in
// clean frames it must still follow the scene, flow_tracker.h.)
#include <cmath>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kFrames = 30;
constexpr double kCornerTolerance = 6.0;  // px, mean corner error of a right report

struct Placed
{
  ShapeId shape;
  amcr::Affine truth;
};

// Large flat shapes (240-260 px): most of their inside is farther from an
// edge than the flow's window reaches.
std::vector<Placed> placements()
{
  const cv::Point2d c = amcr_test::prototypeCentre();
  return {{ShapeId::kArrow, amcr_test::makeAffine(c, {180, 220}, 0.4, 1.25, 1.15, 0.1)},
          {ShapeId::kStar, amcr_test::makeAffine(c, {470, 260}, 2.0, 1.2, 1.3, -0.1)}};
}

/// kFrames frames of the scene: the three shapes drifting slowly to the
/// right over a fixed background (a camera's pan), with Gaussian noise of
/// `noise` grey levels (0: none).
std::vector<cv::Mat> frames(double noise, std::uint64_t seed)
{
  amcr_test::Scene scene;
  for (const Placed& p : placements())
    scene.objects.push_back({p.shape, p.truth});
  scene.clutter.random_shapes = 6;
  scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  scene.clutter.noise_sigma = noise;
  scene.clutter.seed = seed;
  return amcr_test::renderMovingSequence(scene, kFrames, [&](int k) {
    std::vector<amcr_test::Placement> moved = scene.objects;
    for (amcr_test::Placement& m : moved)
      m.prototype_to_image(0, 2) += 0.5 * k;
    return moved;
  });
}

/// The labels reported within the corner tolerance of their truth in the last frame.
std::set<std::string> foundAtTheEnd(const std::vector<cv::Mat>& sequence, std::uint64_t seed)
{
  amcr::Params p;
  p.seed = seed;
  // Built once for every run (immutable; its tables take a while to build).
  static const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar});
  amcr::Recognizer recognizer(p, memory);
  amcr::RecognitionResult result;
  for (const cv::Mat& frame : sequence)
    result = recognizer.step(frame);
  std::set<std::string> found;
  const int last = kFrames - 1;
  for (const Placed& placed : placements())
  {
    amcr::Affine truth = placed.truth;
    truth(0, 2) += 0.5 * last;
    for (const amcr::RecognizedObject& o : result.objects)
      if (o.label == amcr_test::shapeName(placed.shape) &&
          amcr_test::cornerError(o.prototype_to_image, truth) <= kCornerTolerance)
        found.insert(o.label);
  }
  return found;
}

std::string names(const std::set<std::string>& labels)
{
  std::string out;
  for (const std::string& l : labels)
    out += (out.empty() ? "" : ", ") + l;
  return out.empty() ? "none" : out;
}
}  // namespace

TEST(CleanFrames, FindTheSameObjectsAsNoisyOnes)
{
  for (std::uint64_t seed : amcr_test::firstOf<std::uint64_t>({1, 2, 3}, 1))
  {
    const std::set<std::string> clean = foundAtTheEnd(frames(0.0, 500 + seed), seed);
    const std::set<std::string> noisy = foundAtTheEnd(frames(6.0, 500 + seed), seed);
    std::cout << "[ clean    ] seed " << seed << ": by frame " << kFrames << " clean frames gave " << names(clean)
              << "; noisy ones " << names(noisy) << std::endl;
    EXPECT_EQ(clean.size(), placements().size()) << "seed " << seed << ": clean frames missed objects";
    EXPECT_EQ(noisy.size(), placements().size()) << "seed " << seed << ": noisy frames missed objects";
  }
}
