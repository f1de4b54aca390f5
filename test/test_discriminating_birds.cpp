// Attention that discriminates, end to end (the paper's figure 5 problem):
// two drawn birds identical but for a crest on the head. With the competing
// fits (the default) the crested bird shown is decided in fewer frames than
// without them, and with discriminative moves on as well the V-particles
// deciding between the two go to the head.
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
constexpr int kFrames = 40;
const std::vector<std::uint64_t> kSeeds = {1, 2, 3, 4, 5, 6};

struct BirdRun
{
  int held_from = -1;         ///< first frame from which "crested" is reported in every frame; -1: never
  int head_visit = -1;        ///< first frame with a discriminating V-particle near the crest; -1: never
  int wrong_frames = 0;       ///< frames reporting the plain bird where the crested one is
  bool plain_when_taught = false;  ///< the plain bird reported in the frame before the crested one is taught
};

/// The crested bird shown over clutter drawn from `seed`, recognized with
/// discriminative moves on or off and `competing_fits` competing fits per
/// frame; the crested bird's prototype joins the memory (as ~teach adds one)
/// before frame `taught_at` (0: it is there from the start).
BirdRun run(bool moves, int competing_fits, std::uint64_t seed, int taught_at = 0)
{
  amcr::Params params;
  params.seed = seed;
  params.table_cache_dir = "none";
  params.discriminative_moves = moves;
  params.competing_fits = competing_fits;
  // The image's candidates off: the scene measures the competing fits and the
  // discriminative moves on their own. With the candidates on, the crested
  // bird is held from frames 1-4 in all six seeds and the head seldom needs
  // a visit before the decision.
  params.pose_vote_fits = 0;
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("bird", amcr_test::drawSilhouette(amcr_test::drawnBird(false)), params);
  auto taught = std::make_shared<amcr::PrototypeMemory>(*memory);
  taught->add("crested", amcr_test::drawSilhouette(amcr_test::drawnBird(true)), params);

  amcr_test::Scene scene;
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.4, 1.1, 1.0, 0.05);
  scene.objects.push_back({amcr_test::ShapeId::kArrow, truth});  // where the crested bird is drawn
  scene.clutter.seed = 100 + seed;
  const cv::Mat background = amcr_test::renderBackground(scene);  // distractors keep away from the placement
  const std::vector<cv::Point2d> outline = amcr_test::transformPoints(truth, amcr_test::drawnBird(true));
  const cv::Point2d crest = amcr::applyAffine(truth, amcr_test::kCrestTip);
  const cv::Point2d head = amcr::applyAffine(truth, amcr_test::kCrestBase);
  const double head_radius = 0.5 * std::hypot(crest.x - head.x, crest.y - head.y) + 15.0;
  const cv::Point2d head_centre = 0.5 * (crest + head);

  amcr::Recognizer recognizer(params, taught_at > 0 ? memory : taught);
  BirdRun r;
  for (int k = 0; k < kFrames; ++k)
  {
    if (taught_at > 0 && k + 1 == taught_at)
      recognizer.extendMemory(taught);
    cv::Mat clean = background.clone();
    amcr_test::fillPolygon(clean, outline, 35.0);
    const cv::Mat frame = amcr_test::addNoise(clean, scene.clutter.noise_sigma, scene.clutter.seed * 1000 + k);
    bool right = false;
    for (const amcr::RecognizedObject& o : recognizer.step(frame).objects)
    {
      right = right || o.label == "crested";
      r.wrong_frames += o.label == "bird" ? 1 : 0;
      r.plain_when_taught = r.plain_when_taught || (o.label == "bird" && k + 2 == taught_at);
    }
    if (!right)
      r.held_from = -1;
    else if (r.held_from < 0)
      r.held_from = k + 1;
    if (r.head_visit < 0)
      for (const amcr::VParticleView& v : recognizer.view().v)
        if (v.discriminating &&
            std::hypot(v.position.x - head_centre.x, v.position.y - head_centre.y) <= head_radius)
          r.head_visit = k + 1;
  }
  return r;
}

// Under the sanitizers (test/run_length.h) the first two seeds run, with
// each seed's bounds; the comparisons of the totals are over all six.
// Measured (6 seeds, frames from which "crested" is held): with the
// competing fits (the default) 6, 7, 4, 3, 5, 4 (29 in all); without
// 6, 4, 4, 5, 37, 4 (60: with seed 5 the plain bird is held for 32 frames);
// with discriminative moves as well (and their precomputed places, the
// default with the moves) 6, 6, 5, 3, 5, 5 (30), a discriminating
// V-particle near the head by frames 6, 6, 3 and 5 (with seeds 5 and 6 the
// crest is decided at frame 5, before any goes there).
TEST(DiscriminatingBirds, TheCrestDecidesSoonerWithDiscriminativeAttention)
{
  constexpr int kHeldWithin = 20;    // frames: the aim for the paper's three birds
  constexpr int kVisitWithin = 25;   // frames
  constexpr int kSeedsVisiting = 4;  // of the 6
  const int fits = amcr::Params().competing_fits;
  ASSERT_GT(fits, 0) << "the competing fits are on by default";
  const std::vector<std::uint64_t> seeds = amcr_test::firstOf(kSeeds, 2);
  int with_total = 0, without_total = 0, moves_total = 0, visiting = 0, with_wrong = 0, without_wrong = 0;
  for (std::uint64_t seed : seeds)
  {
    const BirdRun with = run(false, fits, seed), without = run(false, 0, seed), moves = run(true, fits, seed);
    std::cout << "[ birds    ] seed " << seed << ": held from frame " << with.held_from << " with the competing fits, "
              << without.held_from << " without, " << moves.held_from
              << " with discriminative moves as well (the head visited at " << moves.head_visit
              << "); the plain bird reported in " << with.wrong_frames << " / " << without.wrong_frames << " / "
              << moves.wrong_frames << " frames\n";
    EXPECT_GT(with.held_from, 0) << "seed " << seed << ": the crested bird is not held to the end";
    EXPECT_LE(with.held_from, kHeldWithin) << "seed " << seed;
    EXPECT_GT(moves.held_from, 0) << "seed " << seed << ", with discriminative moves";
    EXPECT_LE(moves.held_from, kHeldWithin) << "seed " << seed << ", with discriminative moves";
    const auto frames = [](const BirdRun& r) { return r.held_from < 0 ? kFrames + 1 : r.held_from; };
    with_total += frames(with);
    without_total += frames(without);
    moves_total += frames(moves);
    visiting += (moves.head_visit > 0 && moves.head_visit <= kVisitWithin) ? 1 : 0;
    with_wrong += with.wrong_frames;
    without_wrong += without.wrong_frames;
  }
  std::cout << "[ birds    ] total frames to a held decision: " << with_total << " with the competing fits, "
            << without_total << " without, " << moves_total << " with discriminative moves as well\n";
  if (seeds.size() < kSeeds.size())
    return;  // totals over two seeds say nothing: their comparisons are the plain build's
  // A fifth fewer frames in all. Measured: 28 and 28 frames against 45 without. Without them the
  // crested bird's fits that converged a turn off are refined again at its turns onto itself
  // (self_similar_turns.h) since 2026-12-07, which found it sooner there (65 frames before).
  EXPECT_LE(5 * with_total, 4 * without_total);
  EXPECT_LE(5 * moves_total, 4 * without_total);
  EXPECT_LE(with_wrong, without_wrong);
  EXPECT_GE(visiting, kSeedsVisiting) << "discriminating V-particles should go to the head";
}

// The wrong look-alike held first: while only the plain bird is in the
// memory, it is held on the crested bird shown (its outline verifies there
// but for the crest). At frame 16 the crested bird is taught. The pair is
// found alike at once (discriminative_places.h), the crested bird is
// fitted where the plain one is held, verifies better and takes over.
// Measured (6 seeds): "crested" held from frame 16, the teaching's own, in
// every seed; without the fits of a held object's look-alikes from frames
// 21, 36, 23, 27 and never in two seeds (the plain bird held to the end).
TEST(DiscriminatingBirds, ATaughtLookAlikeTakesOverTheHeldObject)
{
  constexpr int kTaughtAt = 16;
  constexpr int kTakenOverWithin = 5;  // frames after the teaching
  for (std::uint64_t seed : amcr_test::firstOf(kSeeds, 2))  // 2 under the sanitizers: test/run_length.h
  {
    const BirdRun r = run(false, amcr::Params().competing_fits, seed, kTaughtAt);
    std::cout << "[ birds    ] seed " << seed << ": the plain bird reported in " << r.wrong_frames
              << " frames; the crested one, taught at frame " << kTaughtAt << ", held from frame " << r.held_from
              << "\n";
    EXPECT_TRUE(r.plain_when_taught) << "seed " << seed << ": the set-up holds the plain bird first";
    EXPECT_LE(r.held_from, kTaughtAt + kTakenOverWithin) << "seed " << seed;
  }
}
}  // namespace
