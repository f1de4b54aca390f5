// amcr::RecognizerSession without ROS (amcr/recognizer_session.h): loads,
// teaching (the running filter goes on), removal and reconfiguration (it
// restarts), their refusals with the reason, the generation check that refuses
// a swap built while another landed, and images recognized with the old filter
// while a rebuild is built.
#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/memory/region_shape.h"
#include "amcr/recognizer_session.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;
using Session = amcr::RecognizerSession;

/// What the session told its host.
struct News
{
  std::vector<std::string> warnings, infos;
  int restarts = 0;
  std::vector<amcr::LabelTable> tables;

  bool saidInfo(const std::string& part) const
  {
    for (const std::string& line : infos)
      if (line.find(part) != std::string::npos)
        return true;
    return false;
  }
};

std::vector<std::string> labels(const amcr::PrototypeMemory& memory)
{
  std::vector<std::string> out;
  for (std::size_t i = 0; i < memory.size(); ++i)
    out.push_back(memory[i].label());
  return out;
}

/// A reconfiguration that sets `params` whatever is in effect, described as `changes`.
Session::ReconfigurationFrom setting(const amcr::Params& params, const std::string& changes = "changed")
{
  return [params, changes](const amcr::Params&) { return Session::Reconfiguration{params, changes}; };
}

/// A directory of arrow, crescent and star; an arrow in the frames; a flag (in no memory) to teach.
class RecognizerSessionTest : public testing::Test
{
protected:
  void SetUp() override
  {
    for (ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
      ASSERT_TRUE(cv::imwrite(dir_.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id)));
    amcr_test::Scene scene;
    scene.objects = {{ShapeId::kArrow,
                      amcr_test::makeAffine(amcr_test::prototypeCentre(), {320.0, 240.0}, 0.5, 1.1, 0.9, 0.15), 35.0}};
    arrow_ = amcr_test::renderClean(scene);
    // The flag alone over clutter (no lines: a line across it would join its outline to the region's border).
    const amcr::Affine flag_at =
        amcr_test::makeAffine(amcr_test::prototypeCentre(), {300.0, 240.0}, 0.2, 1.0, 1.0, 0.0);
    scene.objects = {{ShapeId::kFlag, flag_at, 35.0}};
    scene.clutter.lines = 0;
    scene.clutter.seed = 21;
    flag_ = amcr_test::addNoise(amcr_test::renderClean(scene), 6.0, 2100);
    std::vector<cv::Point2f> outline;
    for (const cv::Point2d& p : amcr_test::transformPoints(flag_at, amcr_test::shapePolygon(ShapeId::kFlag)))
      outline.emplace_back(p);
    const cv::Rect box = cv::boundingRect(outline);
    flag_region_ = amcr::rectangleRegion(box.x - 12, box.y - 12, box.width + 24, box.height + 24);
    params_.seed = 1;
    params_.table_cache_dir = cache_.path();  // the tables are built once for all the tests' loads
  }

  std::unique_ptr<Session> make()
  {
    amcr::SessionHooks hooks;
    hooks.warning = [this](const std::string& text) { news_.warnings.push_back(text); };
    hooks.info = [this](const std::string& text) { news_.infos.push_back(text); };
    hooks.restarted = [this] { ++news_.restarts; };
    hooks.table_changed = [this](const amcr::LabelTable& table) { news_.tables.push_back(table); };
    return std::make_unique<Session>(params_, hooks);
  }

  std::unique_ptr<Session> loaded()
  {
    auto session = make();
    const Session::Loaded answer = session->load(dir_.path());
    EXPECT_EQ(answer.error, "");
    EXPECT_EQ(answer.prototypes, 3u);
    return session;
  }

  /// The next frame of the arrow, recognized.
  amcr::RecognizedFrame step(Session& session, bool restart_unless_fresh = false)
  {
    amcr::FrameInput input;
    input.image = amcr_test::addNoise(arrow_, 6.0, noise_seed_++);
    input.restart_unless_fresh = restart_unless_fresh;
    amcr::RecognizedFrame frame = session.recognize(input);
    EXPECT_TRUE(frame.recognized) << frame.error;
    return frame;
  }
  long iteration(Session& session) { return step(session).result.iteration; }

  amcr_test::TempDir dir_, cache_;
  cv::Mat arrow_, flag_;
  std::vector<cv::Point2f> flag_region_;
  amcr::Params params_;
  News news_;
  std::uint64_t noise_seed_ = 1000;
};

TEST_F(RecognizerSessionTest, ImagesAreSkippedUntilALoadSucceeds)
{
  auto session = make();
  const amcr::RecognizedFrame skipped = session->recognize(arrow_);
  EXPECT_FALSE(skipped.recognized);
  EXPECT_EQ(skipped.error, "") << "no memory is not an error of the image";

  const Session::Loaded bad = session->load(dir_.file("no_such_directory"));
  EXPECT_NE(bad.error.find("no_such_directory"), std::string::npos) << bad.error;
  EXPECT_EQ(bad.prototypes, 0u);
  EXPECT_TRUE(news_.tables.empty()) << "a failed load changed the table";
  EXPECT_FALSE(session->labelTable().memory);

  const Session::Loaded good = session->load(dir_.path());
  ASSERT_EQ(good.error, "");
  EXPECT_EQ(good.prototypes, 3u);
  ASSERT_EQ(news_.tables.size(), 1u);
  EXPECT_EQ(news_.tables[0].version, 1u);
  EXPECT_EQ(news_.tables[0].directory, dir_.path());
  EXPECT_EQ(labels(*news_.tables[0].memory), (std::vector<std::string>{"arrow", "crescent", "star"}));
  EXPECT_TRUE(news_.saidInfo("loaded 3 prototypes")) << "the load was not told";

  const amcr::RecognizedFrame first = step(*session);
  EXPECT_EQ(first.result.iteration, 1);
  EXPECT_TRUE(first.restarted);
  EXPECT_EQ(first.table_version, 1u);
  EXPECT_EQ(first.memory, news_.tables[0].memory);
  ASSERT_NE(first.params, nullptr);
  EXPECT_EQ(first.params->seed, 1u);
  const amcr::RecognizedFrame second = step(*session);
  EXPECT_EQ(second.result.iteration, 2);
  EXPECT_FALSE(second.restarted);
}

TEST_F(RecognizerSessionTest, ResetAndTimeGoingBackRestartTheFilterAFreshOneStays)
{
  auto session = loaded();
  EXPECT_EQ(iteration(*session), 1);
  EXPECT_EQ(iteration(*session), 2);
  const int restarts = news_.restarts;
  EXPECT_EQ(session->reset(), "filter reset: it starts again from the next image");
  EXPECT_EQ(news_.restarts, restarts + 1);
  const amcr::RecognizedFrame fresh = step(*session, true);
  EXPECT_FALSE(fresh.input_restart) << "a fresh filter restarted again";
  EXPECT_EQ(fresh.result.iteration, 1);
  EXPECT_EQ(iteration(*session), 2);
  const amcr::RecognizedFrame back = step(*session, true);
  EXPECT_TRUE(back.input_restart);
  EXPECT_TRUE(back.restarted);
  EXPECT_EQ(back.result.iteration, 1);
}

TEST_F(RecognizerSessionTest, ATaughtShapeJoinsTheRunningFilterWithoutARestart)
{
  auto session = loaded();
  EXPECT_EQ(iteration(*session), 1);
  EXPECT_EQ(iteration(*session), 2);
  ASSERT_TRUE(session->recognize(flag_).recognized);  // iteration 3, the image the flag is cut from
  const int restarts = news_.restarts;

  const Session::Taught taught = session->teach("flag", flag_region_, false);
  ASSERT_EQ(taught.error, "");
  EXPECT_EQ(taught.prototype_id, 3);
  EXPECT_EQ(taught.saved_path, "");
  EXPECT_EQ(taught.table_version, 2u);
  EXPECT_FALSE(std::filesystem::exists(dir_.file("flag.png"))) << "saved without being asked";
  EXPECT_EQ(news_.restarts, restarts) << "teaching restarted the filter";
  ASSERT_EQ(news_.tables.size(), 2u);
  EXPECT_EQ(labels(*news_.tables.back().memory), (std::vector<std::string>{"arrow", "crescent", "star", "flag"}));
  EXPECT_TRUE(news_.saidInfo("taught 'flag'"));

  const amcr::RecognizedFrame next = step(*session);
  EXPECT_EQ(next.result.iteration, 4) << "teaching restarted the filter";
  EXPECT_FALSE(next.restarted);
  EXPECT_EQ(next.memory->size(), 4u);
  EXPECT_EQ(next.table_version, 2u);

  // Saved: the file is where the answer says.
  ASSERT_TRUE(session->recognize(flag_).recognized);
  const Session::Taught saved = session->teach("flag2", flag_region_, true);
  ASSERT_EQ(saved.error, "");
  EXPECT_EQ(saved.saved_path, dir_.file("flag2.png"));
  EXPECT_FALSE(cv::imread(saved.saved_path, cv::IMREAD_UNCHANGED).empty());
}

TEST_F(RecognizerSessionTest, TeachingTheFirstPrototypeStartsTheFilter)
{
  auto session = make();
  ASSERT_FALSE(session->recognize(flag_).recognized);
  const Session::Taught taught = session->teach("flag", flag_region_, false);
  ASSERT_EQ(taught.error, "");
  EXPECT_EQ(taught.prototype_id, 0);
  EXPECT_EQ(session->recognize(flag_).result.iteration, 1);
}

// An image that only views its pixels (a message's buffer) is kept with their owner while it is the last
// image, so that a teach can cut from it after the caller let go; the next image lets the owner go.
TEST_F(RecognizerSessionTest, TheLastImageKeepsTheOwnerOfItsPixels)
{
  auto session = loaded();
  auto buffer = std::make_shared<cv::Mat>(flag_.clone());
  const std::weak_ptr<cv::Mat> watched = buffer;
  amcr::FrameInput input;
  input.image = cv::Mat(buffer->size(), buffer->type(), buffer->data, buffer->step);  // a view, no count
  input.pixels_owner = buffer;
  ASSERT_TRUE(session->recognize(input).recognized);
  input = amcr::FrameInput();
  buffer.reset();
  EXPECT_FALSE(watched.expired()) << "the session let the owner of the last image's pixels go";
  EXPECT_EQ(session->teach("flag", flag_region_, false).error, "");
  step(*session);
  EXPECT_TRUE(watched.expired()) << "the session kept the owner of an image that is no longer the last";
}

TEST_F(RecognizerSessionTest, RefusalsSayWhyAndChangeNothing)
{
  auto scratch = make();  // no directory, no image yet
  EXPECT_NE(scratch->teach("flag", flag_region_, false).error.find("no image received yet"), std::string::npos);
  scratch->recognize(flag_);
  const Session::Taught nowhere = scratch->teach("flag", flag_region_, true);
  EXPECT_NE(nowhere.error.find("nowhere to save"), std::string::npos) << nowhere.error;
  EXPECT_EQ(nowhere.prototype_id, -1);
  EXPECT_NE(scratch->remove("flag").error.find("no label 'flag'"), std::string::npos);
  EXPECT_TRUE(news_.tables.empty());

  auto session = loaded();
  ASSERT_TRUE(session->recognize(flag_).recognized);
  ASSERT_TRUE(cv::imwrite(dir_.file("flag.png"), amcr_test::drawPrototype(ShapeId::kFlag)));  // not loaded
  const std::vector<std::pair<Session::Taught, std::string>> refused = {
      {session->teach("bad/label", flag_region_, false), "character"},
      {session->teach("", flag_region_, false), "empty"},
      {session->teach("arrow", flag_region_, false), "taken"},
      {session->teach("flag", flag_region_, true), "exists"},
      {session->teach("flag", amcr::rectangleRegion(0, 0, 0, 0), false), "empty"},
      {session->teach("flag", amcr::rectangleRegion(5000, 5000, 40, 40), false), "outside"},
  };
  for (const auto& r : refused)
  {
    EXPECT_NE(r.first.error.find(r.second), std::string::npos) << "not '" << r.second << "': " << r.first.error;
    EXPECT_EQ(r.first.prototype_id, -1);
    EXPECT_EQ(r.first.saved_path, "");
    EXPECT_EQ(r.first.table_version, 1u);
  }
  const Session::Removed unknown = session->remove("flag");
  EXPECT_NE(unknown.error.find("no label 'flag'"), std::string::npos) << unknown.error;
  EXPECT_EQ(unknown.removed, 0);
  EXPECT_EQ(session->remove("arrow").error, "");
  EXPECT_EQ(session->remove("crescent").error, "");
  const Session::Removed only = session->remove("star");
  EXPECT_NE(only.error.find("only label"), std::string::npos) << only.error;
  EXPECT_EQ(only.table_version, 3u);
  EXPECT_EQ(labels(*session->labelTable().memory), std::vector<std::string>{"star"});
}

TEST_F(RecognizerSessionTest, ARemovalRestartsTheFilter)
{
  auto session = loaded();
  EXPECT_EQ(iteration(*session), 1);
  EXPECT_EQ(iteration(*session), 2);
  const int restarts = news_.restarts;
  const Session::Removed removed = session->remove("star");
  ASSERT_EQ(removed.error, "");
  EXPECT_EQ(removed.removed, 1);
  EXPECT_EQ(removed.table_version, 2u);
  EXPECT_EQ(news_.restarts, restarts + 1);
  const amcr::RecognizedFrame next = step(*session);
  EXPECT_EQ(next.result.iteration, 1);
  EXPECT_EQ(labels(*next.memory), (std::vector<std::string>{"arrow", "crescent"}));
  EXPECT_TRUE(std::filesystem::exists(dir_.file("star.png"))) << "the file was removed";
}

TEST_F(RecognizerSessionTest, AReconfigurationRebuildsTheFilterAndTheTablesOnlyWhenTheyChange)
{
  auto session = loaded();
  const amcr::RecognizedFrame before = step(*session);
  EXPECT_EQ(iteration(*session), 2);

  amcr::Params changed = params_;
  changed.num_v_particles = 40;
  EXPECT_EQ(session->reconfigure(setting(changed, "num_v_particles 60 -> 40"), false), "");
  EXPECT_EQ(session->params().num_v_particles, 40);
  const amcr::RecognizedFrame after = step(*session);
  EXPECT_EQ(after.result.iteration, 1) << "the filter was not rebuilt";
  EXPECT_EQ(after.memory, before.memory) << "the tables were rebuilt for a parameter that does not build them";
  EXPECT_TRUE(news_.saidInfo("reconfigured (num_v_particles 60 -> 40): filter rebuilt"));

  EXPECT_EQ(session->reconfigure(setting(changed, ""), false), "") << "nothing changed";
  EXPECT_EQ(iteration(*session), 2) << "a reconfiguration that changes nothing restarted the filter";

  changed.prototype_size = 96;  // builds the tables
  EXPECT_EQ(session->reconfigure(setting(changed), false), "");
  const amcr::RecognizedFrame rebuilt = step(*session);
  EXPECT_NE(rebuilt.memory, before.memory) << "the tables were not rebuilt";
  EXPECT_EQ(rebuilt.result.iteration, 1);
  EXPECT_EQ(session->params().prototype_size, 96);

  changed.sigma_w = 7.0;  // builds no table, but the caller asks for them
  EXPECT_EQ(session->reconfigure(setting(changed), true), "");
  EXPECT_NE(step(*session).memory, rebuilt.memory) << "the tables asked for were not rebuilt";
  EXPECT_EQ(news_.tables.size(), 1u) << "the same label table counted as changed";
}

TEST_F(RecognizerSessionTest, ATableRebuildKeepsTheSessionsEdits)
{
  auto session = loaded();
  ASSERT_TRUE(session->recognize(flag_).recognized);
  ASSERT_EQ(session->teach("flag", flag_region_, false).error, "");
  ASSERT_EQ(session->remove("star").error, "");
  const int arrow_width = (*session->labelTable().memory)[0].width();
  amcr::Params changed = params_;
  changed.prototype_size = 96;
  EXPECT_EQ(session->reconfigure(setting(changed), false), "");
  EXPECT_EQ(labels(*session->labelTable().memory), (std::vector<std::string>{"arrow", "crescent", "flag"}));
  EXPECT_LT((*session->labelTable().memory)[0].width(), arrow_width) << "not built with the smaller prototype_size";
}

TEST_F(RecognizerSessionTest, AReconfigurationRefusedKeepsTheParametersInEffect)
{
  auto session = loaded();
  EXPECT_EQ(iteration(*session), 1);
  amcr::Params invalid = params_;
  invalid.sigma_w = 0.0;
  EXPECT_NE(session->reconfigure(setting(invalid), false).find("sigma_w"), std::string::npos);
  const auto refuse = [](const amcr::Params&) -> Session::Reconfiguration {
    throw amcr::ParameterError("num_v_particles -5 is out of its range");
  };
  EXPECT_EQ(session->reconfigure(refuse, false), "num_v_particles -5 is out of its range");
  amcr::Params priors = params_;
  priors.prototype_priors = {{"no_such_label", 1.0}};
  EXPECT_NE(session->reconfigure(setting(priors), false).find("no_such_label"), std::string::npos);
  EXPECT_EQ(session->params().sigma_w, params_.sigma_w);
  EXPECT_TRUE(session->params().prototype_priors.empty());
  EXPECT_EQ(iteration(*session), 2) << "a refused reconfiguration restarted the filter";
}

// The generation check: a swap built while another landed is refused, and nothing changes; built again,
// it lands. Between the build and the swap, images are recognized with the old filter.
TEST_F(RecognizerSessionTest, ASwapIsRefusedWhenAnotherLandedDuringItsBuild)
{
  amcr_test::TempDir other;
  for (ShapeId id : {ShapeId::kArrow, ShapeId::kFlag})
    ASSERT_TRUE(cv::imwrite(other.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id)));
  auto session = loaded();
  EXPECT_EQ(iteration(*session), 1);

  Session::PreparedSwap load = session->prepareLoad(other.path());
  ASSERT_EQ(load.error, "");
  EXPECT_EQ(load.prototypes, 2u);
  const amcr::RecognizedFrame meanwhile = step(*session);
  EXPECT_EQ(meanwhile.result.iteration, 2) << "a prepared load restarted the filter";
  EXPECT_EQ(meanwhile.memory->size(), 3u) << "a prepared load swapped its memory in";
  ASSERT_EQ(session->remove("star").error, "");  // lands first
  EXPECT_EQ(session->commit(load), Session::kMemoryChanged);
  EXPECT_EQ(session->tableVersion(), 2u) << "a refused swap changed the table";
  EXPECT_EQ(iteration(*session), 1);
  EXPECT_EQ(iteration(*session), 2) << "a refused swap restarted the filter";
  EXPECT_EQ(session->labelTable().memory->size(), 2u);
  EXPECT_EQ(session->labelTable().directory, dir_.path());

  load = session->prepareLoad(other.path());
  EXPECT_EQ(session->commit(load), "");
  EXPECT_EQ(session->tableVersion(), 3u);
  EXPECT_EQ(labels(*session->labelTable().memory), (std::vector<std::string>{"arrow", "flag"}));
  EXPECT_EQ(iteration(*session), 1) << "the load did not restart the filter";

  amcr::Params changed = params_;
  changed.num_v_particles = 40;
  Session::PreparedSwap change = session->prepareReconfigure(setting(changed), false);
  ASSERT_EQ(change.error, "");
  EXPECT_EQ(session->load(dir_.path()).error, "");  // lands first
  EXPECT_EQ(session->commit(change), Session::kMemoryChanged);
  EXPECT_EQ(session->params().num_v_particles, params_.num_v_particles);
  EXPECT_EQ(session->commit(change), "") << "a swap committed twice: nothing left to swap";
}

// The build runs without the frame lock: images are recognized, with the previous memory, while a large
// memory loads on another thread.
TEST_F(RecognizerSessionTest, ImagesAreRecognizedWithThePreviousMemoryWhileAMemoryLoads)
{
  amcr_test::TempDir large;
  for (ShapeId id : amcr_test::allShapes())
    ASSERT_TRUE(cv::imwrite(large.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id)));
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
    ASSERT_TRUE(
        cv::imwrite(large.file("random_" + std::to_string(seed) + ".png"), amcr_test::drawRandomSilhouette(seed)));
  params_.table_cache_dir = "none";  // every table is built
  auto session = loaded();
  std::atomic<bool> done{false};
  Session::Loaded answer;
  std::thread loading([&] {
    answer = session->load(large.path());
    done = true;
  });
  int with_the_previous_memory = 0;  // while the load was under way
  while (!done)
    with_the_previous_memory += step(*session).memory->size() == 3u ? 1 : 0;
  loading.join();
  ASSERT_EQ(answer.error, "");
  EXPECT_GE(with_the_previous_memory, 3) << "images waited for the load";
  EXPECT_EQ(step(*session).memory->size(), amcr_test::allShapes().size() + 3);
}
}  // namespace
