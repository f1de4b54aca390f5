// The benchmark's recall funnel (bench/recall_funnel.h) on scenes drawn in code, where the truth is
// known: a shape that is reported passes every stage, and a failure planted at one stage of the
// recognizer is placed at that stage; the sequences' truth files are read with their symmetries,
// and a malformed one is refused by name.
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/recognizer.h"
#include "recall_funnel.h"
#include "scene_drawing.h"
#include "sequence_truth.h"

namespace
{
using amcr_bench::FunnelStage;
using amcr_test::ShapeId;

constexpr int kFrames = 60;

const std::vector<ShapeId> kMemory = {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar};

std::shared_ptr<const amcr::PrototypeMemory> memory()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m = amcr_test::drawnMemory(kMemory);
  return m;
}

/// An arrow 120-150 px across over clutter (the end-to-end test's arrow_101), and its truth.
struct ArrowScene
{
  amcr::Affine truth;
  std::vector<cv::Mat> frames;
  ArrowScene()
  {
    truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {330, 250}, 35 * M_PI / 180, 0.85, 0.75, 0.25);
    amcr_test::Scene scene;
    scene.objects.push_back({ShapeId::kArrow, truth});
    scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
    scene.clutter.seed = 101;
    frames = amcr_test::renderSequence(scene, kFrames);
  }
  amcr_bench::TruthFrame truthFrame() const
  {
    amcr_bench::TruthObject object;
    object.label = "arrow";
    object.prototype_size = cv::Size(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize);
    object.prototype_to_image = {cv::Matx33d(truth(0, 0), truth(0, 1), truth(0, 2), truth(1, 0), truth(1, 1),
                                             truth(1, 2), 0, 0, 1)};
    amcr_bench::TruthFrame frame;
    frame.objects = {object};
    return frame;
  }
};

const ArrowScene& arrowScene()
{
  static const ArrowScene scene;
  return scene;
}

/// Runs the recognizer over the arrow's frames and the funnel after every step.
amcr_bench::FunnelSummary runFunnel(const amcr::Params& params, int* reports = nullptr)
{
  const ArrowScene& scene = arrowScene();
  amcr::Recognizer recognizer(params, memory());
  amcr_bench::FunnelRecorder recorder;
  int reported = 0;
  for (int k = 0; k < kFrames; ++k)
  {
    const amcr::RecognitionResult result = recognizer.step(scene.frames[k]);
    const std::vector<amcr_bench::ObjectFunnel> objects = amcr_bench::measureFunnel(recognizer, result, scene.truthFrame());
    EXPECT_EQ(objects.size(), 1u);
    EXPECT_TRUE(objects[0].in_memory);
    // The funnel's "reported" is the benchmark's right place; the test's own check agrees.
    bool right = false;
    for (const amcr::RecognizedObject& o : result.objects)
      right = right || (o.label == "arrow" && amcr_test::cornerError(o.prototype_to_image, scene.truth) <= 6.0);
    if (right)
    {
      EXPECT_TRUE(objects[0].reported) << "frame " << k;
    }
    reported += objects[0].reported ? 1 : 0;
    recorder.add(k, objects);
  }
  if (reports)
    *reports = reported;
  return recorder.summaries().at(0);
}

amcr::Params defaults(std::uint64_t seed)
{
  amcr::Params p;
  p.seed = seed;
  return p;
}

std::string stage(int index)
{
  return index < 0 ? "none" : amcr_bench::stageName(static_cast<FunnelStage>(index));
}

TEST(RecallFunnel, AReportedShapePassesEveryStage)
{
  int reports = 0;
  const amcr_bench::FunnelSummary s = runFunnel(defaults(1), &reports);
  EXPECT_GT(reports, 0);
  EXPECT_EQ(s.first_missing, -1) << "first missing stage: " << stage(s.first_missing);
  EXPECT_EQ(s.frames, kFrames);
  // Each stage is reached no later than the next one: what is reported was verified, clustered ...
  for (int k = 1; k < amcr_bench::kFunnelStages; ++k)
    EXPECT_LE(s.first_frame[k - 1], s.first_frame[k]) << stage(k - 1) << " after " << stage(k);
}

TEST(RecallFunnel, APrototypeLeftOutOfTheSearchStopsAtTheProposal)
{
  // Prior 0: the arrow is neither seeded nor indexed, so no hypothesis of it is ever proposed.
  amcr::Params params = defaults(1);
  params.prototype_priors = {{"arrow", 0.0}, {"crescent", 1.0}, {"star", 1.0}};
  const amcr_bench::FunnelSummary s = runFunnel(params);
  EXPECT_GT(s.reached[static_cast<int>(FunnelStage::kOnObject)], 0);
  EXPECT_EQ(stage(s.first_missing), "proposed");
}

TEST(RecallFunnel, AnUnreachableClusterShareStopsAtTheCluster)
{
  // Every V-particle re-seeds some of its M-particles each iteration: none holds all in one cluster.
  amcr::Params params = defaults(1);
  params.cluster_min_share = 1.0;
  const amcr_bench::FunnelSummary s = runFunnel(params);
  EXPECT_GT(s.reached[static_cast<int>(FunnelStage::kAlive)], 0);
  EXPECT_EQ(stage(s.first_missing), "cluster");
}

TEST(RecallFunnel, AnUnreachableSupportStopsAtTheReport)
{
  // Every V-particle's support (the most the parameter takes; the attention keeps a few on an
  // object): verified and above the threshold, never reported.
  amcr::Params params = defaults(1);
  params.min_support = params.num_v_particles;
  const amcr_bench::FunnelSummary s = runFunnel(params);
  EXPECT_GT(s.reached[static_cast<int>(FunnelStage::kPassed)], 0);
  EXPECT_EQ(stage(s.first_missing), "reported");
}

TEST(RecallFunnel, AnInstanceHeldOutOfTheMemoryIsJudgedByItsLabelOnly)
{
  // Two instances of "arrow" of the same image size: only the one drawn from the truth's source
  // image is the shape shown.
  auto instances = std::make_shared<amcr::PrototypeMemory>();
  const amcr::Params params = defaults(1);
  instances->add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), params, "arrow/arrow-1.png");
  instances->add("arrow", amcr_test::drawPrototype(ShapeId::kCrescent), params, "arrow/arrow-2.png");
  amcr::Recognizer recognizer(params, instances);
  const amcr::RecognitionResult result = recognizer.step(arrowScene().frames[0]);
  amcr_bench::TruthFrame truth = arrowScene().truthFrame();
  truth.objects[0].source = "arrow-1.png";
  EXPECT_TRUE(amcr_bench::measureFunnel(recognizer, result, truth).at(0).in_memory);
  truth.objects[0].source = "arrow-9.png";
  const amcr_bench::ObjectFunnel held_out = amcr_bench::measureFunnel(recognizer, result, truth).at(0);
  EXPECT_FALSE(held_out.in_memory);
  EXPECT_EQ(held_out.v_on, 0);
  EXPECT_EQ(held_out.best_rank, -1);
}

TEST(SequenceTruth, ReadsMapsAndSymmetries)
{
  amcr_test::TempDir dir;
  const std::string path = dir.path() + "/truth.json";
  std::ofstream(path) << R"({"prototype_sizes": {"mire": [256, 203]}, "targets": [{"label": "mire", "source": "drawn"}],
    "score_points": [[7.5, 7.5], [247.5, 7.5], [247.5, 194.5], [7.5, 194.5]], "symmetries": [[0, 1, 2, 3], [2, 3, 0, 1]],
    "frames": [{"frame": 0, "unknown": true, "objects": [{"label": "mire"}]},
               {"frame": 1, "objects": [{"label": "mire", "homography": [[1, 0, 10], [0, 1, 20], [0, 0, 1]]}]},
               {"frame": 2, "objects": [{"label": "mire", "prototype_to_image": [[2, 0, 0], [0, 2, 0]]}]}]})";
  const std::vector<amcr_bench::TruthFrame> frames = amcr_bench::readSequenceTruth(path);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_FALSE(frames[0].known);
  ASSERT_TRUE(frames[1].known);
  ASSERT_EQ(frames[1].objects.size(), 1u);
  const amcr_bench::TruthObject& o = frames[1].objects[0];
  EXPECT_EQ(o.prototype_size, cv::Size(256, 203));
  EXPECT_EQ(o.source, "drawn");
  ASSERT_EQ(o.prototype_to_image.size(), 2u);  // the identity and the half turn of the score points
  const cv::Vec3d corner = o.prototype_to_image[1] * cv::Vec3d(7.5, 7.5, 1.0);
  EXPECT_NEAR(corner[0] / corner[2], 247.5 + 10, 1e-6);  // point 0 maps where the truth maps point 2
  EXPECT_NEAR(corner[1] / corner[2], 194.5 + 20, 1e-6);
  EXPECT_DOUBLE_EQ(frames[2].objects[0].prototype_to_image[0](0, 0), 2.0);
}

TEST(SequenceTruth, RefusesAMalformedFileByName)
{
  amcr_test::TempDir dir;
  const std::string path = dir.path() + "/truth.json";
  std::ofstream(path) << R"({"prototype_sizes": {"a": [10, 10]},
    "frames": [{"frame": 0, "objects": [{"label": "a", "prototype_to_image": [[1, 0, 0]]}]}]})";
  try
  {
    amcr_bench::readSequenceTruth(path);
    FAIL() << "a map of one row was accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rows"), std::string::npos) << e.what();
  }
  EXPECT_THROW(amcr_bench::readSequenceTruth(dir.path() + "/missing.json"), std::runtime_error);
}
}  // namespace
