// Recognition while tracking, with inputs drawn in code: an object
// moving over clutter (up to 5 px and 3 degrees per frame) followed by the
// V-particles riding the optical flow; several objects at once with their
// own affines and track ids; a frame budget that splits iterations over
// frames; jumps in the sequence.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/exploration_policy.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::Placement;
using amcr_test::ShapeId;

constexpr double kCornerTolerance = 8.0;  // px, mean corner error of prototype_to_image while moving
constexpr double kStaticTolerance = 6.0;  // px, the same for a static object (as the end-to-end test)
// Of the frames after the first correct decision, over recognizer seeds 1-6
// together: measured 94.3 % (seeds 1-9: 95.3 %; with one absolute edge
// threshold 94.4 % and 93.7 %). A seed alone ranges 85-100 %: a pose held
// 9-11 px off at the prototype's corners for 10-30 frames before it is
// refined back.
constexpr double kMinHeldShare = 0.93;
// (2 under the sanitizers: test/run_length.h)
constexpr std::uint64_t kTrackingSeeds = amcr_test::runLength(6, 2);

std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const auto m = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar});
  return m;
}

amcr::Params params(bool flow, std::uint64_t seed = 1)
{
  amcr::Params p;
  p.seed = seed;
  p.optical_flow = flow;
  return p;
}

amcr_test::Clutter clutter(std::uint64_t seed) { return amcr_test::distractorClutter(seed); }

// The moving object: its centre on a Lissajous path (each axis at most
// 3.5 px per frame, together at most 5) and a rotation of 2 to 3 degrees
// per frame, under an anisotropic scale and a shear.
amcr::Affine movingPose(int frame)
{
  const double t = 2.0 * M_PI * frame / 200.0;
  const cv::Point2d centre(320.0 + 110.0 * std::sin(t), 240.0 + 55.0 * std::sin(2.0 * t));
  const double degrees = 20.0 + 2.5 * frame + 0.5 * 200.0 / (2.0 * M_PI) * (1.0 - std::cos(t));
  return amcr_test::makeAffine(amcr_test::prototypeCentre(), centre, degrees * M_PI / 180.0, 0.6, 0.52, 0.15);
}

struct TrackingRun
{
  int frames = 0;
  int first_correct = -1;  // 0-based frame of the first correct report
  int held = 0;            // frames from first_correct on with a correct report
  int wrong_label = 0;     // frames from first_correct on with a report of another label
  int reseeded = 0;        // V-particles re-seeded by failed flows
  std::set<int> track_ids;  // of the correct reports
  std::vector<double> errors;  // corner errors of the correct label's reports

  int since() const { return first_correct >= 0 ? frames - first_correct : 0; }
  std::string summary() const
  {
    std::vector<double> sorted = errors;
    std::sort(sorted.begin(), sorted.end());
    std::ostringstream out;
    out << "first correct at frame " << first_correct << ", held in " << held << " of " << since()
        << " frames since, another label in " << wrong_label << ", median corner error "
        << (sorted.empty() ? -1.0 : sorted[sorted.size() / 2]) << " px, " << track_ids.size() << " track id(s), "
        << reseeded << " V-particles re-seeded by failed flows";
    return out.str();
  }
};

TrackingRun runMoving(bool flow, const std::vector<cv::Mat>& frames, std::uint64_t seed = 1)
{
  amcr::Recognizer recognizer(params(flow, seed), memory());
  TrackingRun run;
  run.frames = static_cast<int>(frames.size());
  for (int k = 0; k < run.frames; ++k)
  {
    const amcr::RecognitionResult result = recognizer.step(frames[k]);
    run.reseeded += result.flow_failures;
    bool correct = false, wrong = false;
    for (const amcr::RecognizedObject& o : result.objects)
    {
      if (o.label != "arrow")
      {
        wrong = true;
        continue;
      }
      const double e = amcr_test::cornerError(o.prototype_to_image, movingPose(k));
      run.errors.push_back(e);
      if (e <= kCornerTolerance)
      {
        correct = true;
        run.track_ids.insert(o.track_id);
      }
    }
    if (correct && run.first_correct < 0)
      run.first_correct = k;
    if (run.first_correct >= 0)
    {
      run.held += correct;
      run.wrong_label += wrong;
    }
  }
  return run;
}

// The moving sequence: 200 frames; after the first correct decision the
// arrow must be reported with its label and within the corner tolerance in at
// least kMinHeldShare of the frames, over the runs of kTrackingSeeds seeds
// together (one run's share is chance, above). The same frames without
// the flow are run beside the first and printed (an ablation, not asserted).
TEST(Tracking, FollowsAMovingObjectWithTheFlow)
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kArrow, movingPose(0)});
  scene.clutter = clutter(301);
  const std::vector<cv::Mat> frames = amcr_test::renderMovingSequence(
      scene, 200, [](int k) { return std::vector<Placement>{{ShapeId::kArrow, movingPose(k)}}; });

  int held = 0, since = 0, wrong_label = 0;
  for (std::uint64_t seed = 1; seed <= kTrackingSeeds; ++seed)
  {
    const TrackingRun with_flow = runMoving(true, frames, seed);
    std::cout << "[ tracking ] seed " << seed << " with flow: " << with_flow.summary() << std::endl;
    ASSERT_GE(with_flow.first_correct, 0) << "seed " << seed << ": " << with_flow.summary();
    held += with_flow.held;
    since += with_flow.since();
    wrong_label += with_flow.wrong_label;
  }
  RecordProperty("held_with_flow", held);
  if (!amcr_test::kShortRuns)  // the ablation is printed, not asserted: not run under the sanitizers
  {
    const TrackingRun without_flow = runMoving(false, frames);
    std::cout << "[ tracking ] seed 1 without flow: " << without_flow.summary() << std::endl;
    RecordProperty("held_without_flow", without_flow.held);
  }

  EXPECT_GE(held, kMinHeldShare * since) << "held in " << held << " of " << since << " frames over " << kTrackingSeeds << " seeds";
  EXPECT_LE(wrong_label, (1.0 - kMinHeldShare) * since) << "another label in " << wrong_label << " of " << since;
}
}  // namespace

namespace
{
/// Steps `recognizer` over `frames`; returns the objects of each frame.
std::vector<std::vector<amcr::RecognizedObject>> runStatic(amcr::Recognizer& recognizer,
                                                           const std::vector<cv::Mat>& frames)
{
  std::vector<std::vector<amcr::RecognizedObject>> objects;
  for (const cv::Mat& frame : frames)
    objects.push_back(recognizer.step(frame).objects);
  return objects;
}

/// The reported object of `label` within `tolerance` px of `truth`, or null.
const amcr::RecognizedObject* find(const std::vector<amcr::RecognizedObject>& objects, const std::string& label,
                                   const amcr::Affine& truth, double tolerance)
{
  for (const auto& o : objects)
    if (o.label == label && amcr_test::cornerError(o.prototype_to_image, truth) <= tolerance)
      return &o;
  return nullptr;
}

/// Frames (of the last `window`) in which every placement is reported with
/// its label within the static tolerance by an object of its own.
int framesWithAll(const std::vector<std::vector<amcr::RecognizedObject>>& objects,
                  const std::vector<Placement>& placements, std::size_t window, std::set<int>* track_ids = nullptr)
{
  int count = 0;
  for (std::size_t k = objects.size() - std::min(window, objects.size()); k < objects.size(); ++k)
  {
    std::set<const amcr::RecognizedObject*> found;
    for (const Placement& p : placements)
      found.insert(find(objects[k], amcr_test::shapeName(p.shape), p.prototype_to_image, kStaticTolerance));
    if (found.count(nullptr) == 0 && found.size() == placements.size())
    {
      ++count;
      if (track_ids)
        for (const auto* o : found)
          track_ids->insert(o->track_id);
    }
  }
  return count;
}
}  // namespace

// Two different known shapes in one frame: both reported, each with its own
// affine (within the static tolerance of its truth), in most of the last
// 30 of 150 frames.
TEST(SeveralObjects, TwoDifferentShapesEachWithItsOwnAffine)
{
  amcr_test::Scene scene;
  scene.objects = {{ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {180, 230}, 0.5, 0.8, 0.7, 0.2)},
                   {ShapeId::kStar, amcr_test::makeAffine(amcr_test::prototypeCentre(), {470, 250}, -0.8, 0.75, 0.85, -0.1)}};
  scene.clutter = clutter(311);
  scene.clutter.random_shapes = 4;
  amcr::Recognizer recognizer(params(true), memory());
  const auto objects = runStatic(recognizer, amcr_test::renderSequence(scene, 150));
  const int both = framesWithAll(objects, scene.objects, 30);
  std::cout << "[ several  ] arrow and star both reported in " << both << " of the last 30 frames" << std::endl;
  EXPECT_GE(both, 25);
}

// Two copies of one shape (different poses): two objects with different
// track ids, each with its own affine.
TEST(SeveralObjects, TwoCopiesOfOneShapeAreTwoTracks)
{
  amcr_test::Scene scene;
  scene.objects = {
      {ShapeId::kCrescent, amcr_test::makeAffine(amcr_test::prototypeCentre(), {170, 240}, 0.3, 0.8, 0.8, 0.0)},
      {ShapeId::kCrescent, amcr_test::makeAffine(amcr_test::prototypeCentre(), {460, 230}, 2.2, 0.75, 0.85, 0.2)}};
  scene.clutter = clutter(312);
  scene.clutter.random_shapes = 4;
  amcr::Recognizer recognizer(params(true), memory());
  const auto objects = runStatic(recognizer, amcr_test::renderSequence(scene, 150));
  std::set<int> ids;
  const int both = framesWithAll(objects, scene.objects, 30, &ids);
  std::cout << "[ several  ] both crescents reported in " << both << " of the last 30 frames, track ids";
  for (int id : ids)
    std::cout << " " << id;
  std::cout << std::endl;
  EXPECT_GE(both, 25);
  // Each frame's two objects carry different ids (framesWithAll found two
  // distinct objects); over the window the ids stay those two.
  EXPECT_EQ(ids.size(), 2u);
}

/// The frame budget on a clock of the test's own: every V-particle update
/// costs `update_ms` of it (the exploration policy, called once per update,
/// counts the updates) and nothing else takes time, so the budget's
/// decisions are exact and need no calibration against the machine. The
/// count is atomic: the policy is called from every thread of an iteration.
class CostedPolicy : public amcr::ExplorationPolicy
{
public:
  CostedPolicy(const amcr::Params& p, std::shared_ptr<std::atomic<long>> updates)
    : reflect_(p.v_step, p.reflection_jitter), updates_(std::move(updates))
  {
  }
  amcr::Control decide(const amcr::VParticle& v, const amcr::RadialScanner& scanner, amcr::Rng& rng) const override
  {
    updates_->fetch_add(1);
    return reflect_.decide(v, scanner, rng);
  }

private:
  amcr::ReflectAtEdgesPolicy reflect_;
  std::shared_ptr<std::atomic<long>> updates_;
};

/// Puts `recognizer` on a fake clock on which each V-particle update costs `update_ms`.
void costUpdates(amcr::Recognizer& recognizer, double update_ms)
{
  const auto updates = std::make_shared<std::atomic<long>>(0);
  recognizer.setClock([updates, update_ms] { return static_cast<double>(updates->load()) * update_ms; });
  recognizer.setPolicy(std::make_unique<CostedPolicy>(recognizer.params(), updates));
}

constexpr double kUpdateMs = 1.0;  // fake ms per V-particle update

// A frame budget of half the updates of an iteration (60 V-particles at
// 1 ms each, 30 ms) splits the rounds over frames: no frame after the first
// (whose estimates start at 0) runs more updates than fit, less than one
// iteration per frame on average, and the object of the end-to-end test is
// still recognized, within more frames.
TEST(FrameBudget, SplitIterationsStillRecognize)
{
  amcr_test::Scene scene;
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 0.6, 0.85, 0.75, 0.25);
  scene.objects.push_back({ShapeId::kArrow, truth});
  scene.clutter = clutter(101);
  amcr::Params p = params(true);
  p.frame_budget_ms = 30.0;
  const int fitting_updates = static_cast<int>(p.frame_budget_ms / kUpdateMs);

  amcr::Recognizer recognizer(p, memory());
  costUpdates(recognizer, kUpdateMs);
  // 400 frames (200 under the sanitizers: test/run_length.h); found at frame 41 and held after.
  const std::vector<cv::Mat> frames = amcr_test::renderSequence(scene, amcr_test::runLength(400, 200));
  double iterations = 0.0;
  int first = -1, held = 0;
  for (int k = 0; k < static_cast<int>(frames.size()); ++k)
  {
    const amcr::RecognitionResult result = recognizer.step(frames[k]);
    iterations += result.iterations;
    EXPECT_GT(result.iterations, 0.0);
    EXPECT_LE(result.iterations, 1.0);
    const int updates = static_cast<int>(std::lround(result.iterations * p.num_v_particles));
    EXPECT_DOUBLE_EQ(result.time_ms, updates * kUpdateMs) << "frame " << k << ": time_ms is not the clock's";
    if (k > 0)
    {
      EXPECT_LE(updates, fitting_updates) << "frame " << k;
    }
    const bool correct = find(result.objects, "arrow", truth, kStaticTolerance) != nullptr;
    if (correct && first < 0)
      first = k;
    if (first >= 0)
      held += correct;
  }
  const double per_frame = iterations / frames.size();
  std::cout << "[ budget   ] budget " << p.frame_budget_ms << " ms at " << kUpdateMs << " ms per update: "
            << per_frame << " iterations per frame, first correct at frame " << first << ", held in " << held
            << " of " << (first >= 0 ? static_cast<int>(frames.size()) - first : 0) << std::endl;
  EXPECT_LT(per_frame, 0.9) << "the budget did not split the iterations";
  EXPECT_EQ(recognizer.iteration(), static_cast<long>(std::floor(iterations + 1e-6)));
  ASSERT_GE(first, 0) << "never recognized under the budget";
  EXPECT_GE(held, 0.8 * (static_cast<int>(frames.size()) - first));
}

// reset() forgets the frame budget's time estimates: after frames of
// expensive updates, the first frame after a reset runs as many updates as
// the first frame of a new recognizer.
TEST(FrameBudget, ResetForgetsTheTimeEstimates)
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 0.6, 0.85, 0.75, 0.25)});
  scene.clutter = clutter(101);
  const cv::Mat frame = amcr_test::renderClean(scene);
  amcr::Params p = params(false);
  p.frame_budget_ms = 30.0;

  amcr::Recognizer fresh(p, memory());
  costUpdates(fresh, kUpdateMs);
  const double first = fresh.step(frame).iterations;

  amcr::Recognizer used(p, memory());
  costUpdates(used, 10.0 * kUpdateMs);
  for (int k = 0; k < 5; ++k)
    used.step(frame);
  used.reset();
  costUpdates(used, kUpdateMs);
  EXPECT_EQ(used.step(frame).iterations, first) << "the time estimates of the expensive frames outlived reset()";
}

// Jumps: a different scene re-seeds the V-particles whose flow fails and the
// new object is recognized; a change of resolution re-seeds everything.
// [measured with the objects' life cycle (held objects keep V-particles),
// seeds 1-6: the star found with 5, in 97-111 of 120 frames; seed 1 never]
TEST(Jumps, ANewSceneAndANewResolutionReseedWithoutACrash)
{
  amcr_test::Scene first;
  first.objects.push_back({ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 0.6, 0.85, 0.75, 0.25)});
  first.clutter = clutter(101);
  amcr_test::Scene second;
  const amcr::Affine star = amcr_test::makeAffine(amcr_test::prototypeCentre(), {290, 250}, -0.35, 0.95, 0.85, -0.2);
  second.objects.push_back({ShapeId::kStar, star});
  second.clutter = clutter(106);
  amcr_test::Scene small;
  const amcr::Affine small_star = amcr_test::makeAffine(amcr_test::prototypeCentre(), {160, 120}, 0.9, 0.6, 0.55, 0.1);
  small.size = cv::Size(320, 240);
  small.objects.push_back({ShapeId::kStar, small_star});
  small.clutter = clutter(107);
  small.clutter.random_shapes = 2;
  small.clutter.lines = 4;

  // The jump, over three seeds (two under the sanitizers): the star is found
  // after it with all but one (whether one seed finds it in 120 frames is chance).
  const int seeds = amcr_test::runLength(3, 2);
  const std::vector<cv::Mat> first_frames = amcr_test::renderSequence(first, 30);
  const std::vector<cv::Mat> second_frames = amcr_test::renderSequence(second, 120);
  std::unique_ptr<amcr::Recognizer> recognizer;
  int found_with = 0, reseeded = 0, star_frames = 0;
  for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed)
  {
    amcr::Params p = params(true);
    p.seed = seed;
    recognizer = std::make_unique<amcr::Recognizer>(p, memory());
    runStatic(*recognizer, first_frames);
    const amcr::RecognitionResult jump = recognizer->step(second_frames[0]);
    EXPECT_GT(jump.flow_failures, 0) << "no V-particle noticed the jump (seed " << seed << ")";
    reseeded += jump.flow_failures;
    int frames = 0;
    for (const auto& objects : runStatic(*recognizer, second_frames))
      frames += find(objects, "star", star, kStaticTolerance) != nullptr;
    found_with += frames > 0 ? 1 : 0;
    star_frames += frames;
  }
  EXPECT_GE(found_with, seeds - 1) << "the star of the new scene was recognized with " << found_with << " of " << seeds
                                   << " seeds";

  const auto after_resize = runStatic(*recognizer, amcr_test::renderSequence(small, 120));
  for (const amcr::VParticle& v : recognizer->vParticles())
  {
    EXPECT_LT(v.x, 320.f);
    EXPECT_LT(v.y, 240.f);
  }
  int small_frames = 0;
  for (const auto& objects : after_resize)
    small_frames += find(objects, "star", small_star, kStaticTolerance) != nullptr;
  std::cout << "[ jumps    ] new scene, " << seeds << " seeds: " << reseeded << " V-particles re-seeded, star found with "
            << found_with
            << " seeds, in " << star_frames << " of " << 120 * seeds << " frames; at 320x240: star in " << small_frames
            << " of 120 frames"
            << std::endl;
  EXPECT_GT(small_frames, 0) << "the star at the new resolution was never recognized";
}
