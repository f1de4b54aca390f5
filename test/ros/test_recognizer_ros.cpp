// amcr_ros::RecognizerRos on its own (no nodelet, no topics in between): built
// from plain node handles against the rostest master, fed drawn images through
// process(), and reset, reloaded and reconfigured through its methods; the
// rebuilds' two steps (prepare without the lock, commit under it) with another
// edit in between, and images recognized while a memory loads.
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include <cv_bridge/cv_bridge.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>

#include "../scene_drawing.h"
#include "reconfigure_request.h"
#include "reconfigure.h"
#include "recognizer_ros.h"

namespace
{
using amcr_test::ShapeId;
using amcr_ros::RecognizerRos;

class RecognizerRosTest : public testing::Test
{
protected:
  void SetUp() override
  {
    for (ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
      cv::imwrite(dir_.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));
    scene_.objects = {{ShapeId::kArrow,
                       amcr_test::makeAffine(amcr_test::prototypeCentre(), {320.0, 240.0}, 0.5, 1.1, 0.9, 0.15), 35.0}};
    scene_.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
    clean_ = amcr_test::renderClean(scene_);
  }

  /// A RecognizerRos in its own private namespace, started with `prototypes` (may be empty);
  /// `table_cache_dir` "none" builds every table.
  std::unique_ptr<RecognizerRos> make(const std::string& prototypes, const std::string& table_cache_dir = "")
  {
    const std::string name = "~recognizer_" + std::to_string(instances_++);
    ros::NodeHandle private_nh(name);
    namespace_ = private_nh.getNamespace();
    private_nh.setParam("config", std::string(AMCR_SOURCE_DIR) + "/config/amcr.yaml");
    private_nh.setParam("seed", 1);
    private_nh.setParam("prototypes", prototypes);
    if (!table_cache_dir.empty())
      private_nh.setParam("table_cache_dir", table_cache_dir);
    return std::make_unique<RecognizerRos>(ros::NodeHandle(), private_nh);
  }

  /// The size of the memory the next frame is recognized with.
  std::size_t memorySize(RecognizerRos& recognizer, double seconds)
  {
    RecognizerRos::Frame out;
    EXPECT_TRUE(recognizer.process(frame(seconds), false, out));
    return out.memory ? out.memory->size() : 0;
  }

  /// The next frame of the scene, mono8, `seconds` after the start (the stream's clock).
  sensor_msgs::ImageConstPtr frame(double seconds)
  {
    std_msgs::Header header;
    header.stamp = ros::Time(1000.0 + seconds);
    header.frame_id = "camera";
    const cv::Mat image = amcr_test::addNoise(clean_, scene_.clutter.noise_sigma, noise_seed_++);
    return cv_bridge::CvImage(header, sensor_msgs::image_encodings::MONO8, image).toImageMsg();
  }

  /// Processes the frame at `seconds`; the iteration it reports.
  long step(RecognizerRos& recognizer, double seconds)
  {
    RecognizerRos::Frame out;
    EXPECT_TRUE(recognizer.process(frame(seconds), false, out));
    return out.message.iteration;
  }

  /// Sets one int through the dynamic_reconfigure service of the last RecognizerRos made, as
  /// `dynparam set` does; the configuration the server answers with.
  dynamic_reconfigure::Config setThroughServer(const std::string& name, int value)
  {
    dynamic_reconfigure::Reconfigure call = amcr_test::intParameterRequest(name, value);
    EXPECT_TRUE(ros::service::call(namespace_ + "/set_parameters", call)) << namespace_ << "/set_parameters";
    return call.response.config;
  }

  std::string namespace_;
  amcr_test::TempDir dir_;
  amcr_test::Scene scene_;
  cv::Mat clean_;
  std::uint64_t noise_seed_ = 1000;
  static int instances_;
};
int RecognizerRosTest::instances_ = 0;

TEST_F(RecognizerRosTest, SkipsImagesUntilALoadSucceeds)
{
  auto recognizer = make(dir_.file("missing"));
  RecognizerRos::Frame out;
  EXPECT_FALSE(recognizer->process(frame(0.0), false, out)) << "an image processed without prototypes";

  const amcr::LoadPrototypes::Response bad = recognizer->loadPrototypes(dir_.file("no_such_directory"));
  EXPECT_FALSE(bad.success);
  EXPECT_NE(bad.message.find("no_such_directory"), std::string::npos) << bad.message;

  const amcr::LoadPrototypes::Response good = recognizer->loadPrototypes(dir_.path());
  ASSERT_TRUE(good.success) << good.message;
  EXPECT_EQ(good.num_prototypes, 3);
  EXPECT_EQ(step(*recognizer, 0.1), 1);
}

// The message mirrors the core's result: its objects in the core's order (best
// score first) and its time; the overlay only when asked for.
TEST_F(RecognizerRosTest, MessagesKeepTheCoreOrderAndTime)
{
  auto recognizer = make(dir_.path());
  bool seen_objects = false;
  for (int k = 0; k < 100 && !seen_objects; ++k)
  {
    RecognizerRos::Frame out;
    ASSERT_TRUE(recognizer->process(frame(0.1 * k), false, out));
    EXPECT_TRUE(out.overlay.empty());
    ASSERT_TRUE(out.memory);
    EXPECT_EQ(out.message.processing_ms, out.result.time_ms);
    EXPECT_EQ(out.message.header.frame_id, "camera");
    ASSERT_EQ(out.message.objects.size(), out.result.objects.size());
    for (std::size_t i = 0; i < out.result.objects.size(); ++i)
    {
      EXPECT_EQ(out.message.objects[i].label, out.result.objects[i].label);
      EXPECT_EQ(out.message.objects[i].track_id, out.result.objects[i].track_id);
      EXPECT_EQ(out.message.objects[i].score, out.result.objects[i].score);
      EXPECT_FALSE(out.message.objects[i].pose_valid);
      if (i > 0)
      {
        EXPECT_GE(out.result.objects[i - 1].score, out.result.objects[i].score) << "not best score first";
      }
    }
    seen_objects = !out.result.objects.empty();
  }
  EXPECT_TRUE(seen_objects) << "the arrow was not recognized within 100 frames";

  RecognizerRos::Frame drawn;
  ASSERT_TRUE(recognizer->process(frame(20.0), true, drawn));
  EXPECT_EQ(drawn.overlay.type(), CV_8UC3);
  EXPECT_GT(drawn.overlay.cols, clean_.cols);
}

// ~reset, a reload, a reconfiguration and time going backwards all restart the filter.
TEST_F(RecognizerRosTest, EveryResetRestartsTheFilter)
{
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);
  EXPECT_EQ(step(*recognizer, 0.1), 2);

  recognizer->reset();
  EXPECT_EQ(step(*recognizer, 0.2), 1);
  EXPECT_EQ(step(*recognizer, 0.3), 2);

  EXPECT_EQ(step(*recognizer, 0.1), 1) << "time went backwards without a reset";
  EXPECT_EQ(step(*recognizer, 0.4), 2);

  ASSERT_TRUE(recognizer->loadPrototypes(dir_.path()).success);
  EXPECT_EQ(step(*recognizer, 0.5), 1);
  EXPECT_EQ(step(*recognizer, 0.6), 2);

  amcr::AMCRConfig config = amcr_ros::toConfig(recognizer->params());
  config.num_v_particles = 40;
  EXPECT_EQ(recognizer->reconfigure(config, 0), "");
  EXPECT_EQ(recognizer->params().num_v_particles, 40);
  EXPECT_EQ(step(*recognizer, 0.7), 1);
}

// A value out of range is refused naming it; the configuration in use stays, and so does the filter.
TEST_F(RecognizerRosTest, ReconfigureRefusesAnInvalidValueNamingIt)
{
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);
  amcr::AMCRConfig config = amcr_ros::toConfig(recognizer->params());
  config.sigma_w = 0.0;
  config.num_v_particles = 40;
  const std::string error = recognizer->reconfigure(config, 0);
  EXPECT_NE(error.find("sigma_w"), std::string::npos) << error;
  EXPECT_EQ(config.sigma_w, 5.0) << "the refused value is still shown";
  EXPECT_EQ(config.num_v_particles, 60);
  EXPECT_EQ(recognizer->params().num_v_particles, 60);
  EXPECT_EQ(step(*recognizer, 0.1), 2) << "a refused reconfiguration restarted the filter";
}

int intValue(const dynamic_reconfigure::Config& config, const std::string& name)
{
  for (const auto& p : config.ints)
    if (p.name == name)
      return p.value;
  ADD_FAILURE() << name << " is not in the configuration";
  return 0;
}

// The server used to clamp -5 V-particles to 1 before the callback saw it, and apply it; now the value
// reaches RecognizerRos, which refuses it and keeps what is in effect, in the server too.
TEST_F(RecognizerRosTest, ReconfigureServiceRefusesAnOutOfRangeValueInsteadOfClampingIt)
{
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);
  const dynamic_reconfigure::Config shown = setThroughServer("num_v_particles", -5);
  EXPECT_EQ(intValue(shown, "num_v_particles"), 60) << "the server shows a value not in effect";
  EXPECT_EQ(recognizer->params().num_v_particles, 60) << "-5 was clamped and applied";
  EXPECT_EQ(step(*recognizer, 0.1), 2) << "a refused reconfiguration restarted the filter";

  amcr::AMCRConfig config = amcr_ros::toConfig(recognizer->params());
  config.num_v_particles = -5;
  const std::string error = recognizer->reconfigure(config, 0);
  for (const char* part : {"num_v_particles", "-5", "[1, 5000]"})
    EXPECT_NE(error.find(part), std::string::npos) << part << " not in: " << error;
  EXPECT_EQ(config.num_v_particles, 60);

  EXPECT_EQ(intValue(setThroughServer("num_v_particles", 40), "num_v_particles"), 40);
  EXPECT_EQ(recognizer->params().num_v_particles, 40) << "a valid value after a refused one";
}

// A change of prototype_priors alone is applied; refused priors leave the configuration in effect (in
// `config`, which the server keeps) and do not spoil the next, unrelated change.
TEST_F(RecognizerRosTest, ReconfigureAppliesAndRefusesPriorsAlone)
{
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);
  amcr::AMCRConfig config = amcr_ros::toConfig(recognizer->params());
  config.prototype_priors = "arrow: 2";
  EXPECT_EQ(recognizer->reconfigure(config, 0), "");
  const std::map<std::string, double> arrow_twice = {{"arrow", 2.0}};
  EXPECT_EQ(recognizer->params().prototype_priors, arrow_twice) << "a change of the priors alone was dropped";
  EXPECT_EQ(step(*recognizer, 0.1), 1) << "new priors did not restart the filter";

  config.prototype_priors = "no_such_label: 1";
  const std::string error = recognizer->reconfigure(config, 0);
  EXPECT_NE(error.find("no_such_label"), std::string::npos) << error;
  EXPECT_EQ(config.prototype_priors, amcr::formatPriors(arrow_twice)) << "the refused priors are still shown";
  EXPECT_EQ(recognizer->params().prototype_priors, arrow_twice);

  config.num_v_particles = 40;
  EXPECT_EQ(recognizer->reconfigure(config, 0), "") << "the next change is refused";
  EXPECT_EQ(recognizer->params().num_v_particles, 40);
  EXPECT_EQ(recognizer->params().prototype_priors, arrow_twice);
}

// The generation check: a load built while another edit landed is refused at the swap, and nothing
// changes (memory, table version, the running filter); built again, it lands.
TEST_F(RecognizerRosTest, ALoadIsRefusedWhenTheMemoryChangedDuringItsBuild)
{
  amcr_test::TempDir other;
  for (ShapeId id : {ShapeId::kArrow, ShapeId::kFlag})
    cv::imwrite(other.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);

  RecognizerRos::PreparedSwap load = recognizer->prepareLoad(other.path());
  ASSERT_TRUE(load.error.empty()) << load.error;
  const amcr::RemovePrototype::Response removed = recognizer->removePrototype("star");  // lands first
  ASSERT_TRUE(removed.success) << removed.message;
  EXPECT_EQ(step(*recognizer, 0.1), 1) << "the removal restarts the filter";

  EXPECT_EQ(recognizer->commit(load), RecognizerRos::kMemoryChanged);
  EXPECT_EQ(recognizer->tableVersion(), removed.table_version) << "a refused swap changed the table";
  EXPECT_EQ(step(*recognizer, 0.2), 2) << "a refused swap restarted the filter";
  EXPECT_EQ(memorySize(*recognizer, 0.3), 2u) << "not the memory without 'star'";

  load = recognizer->prepareLoad(other.path());
  EXPECT_EQ(recognizer->commit(load), "");
  EXPECT_EQ(recognizer->tableVersion(), removed.table_version + 1);
  EXPECT_EQ(memorySize(*recognizer, 0.4), 2u);
  EXPECT_EQ(step(*recognizer, 0.5), 2) << "the load did not restart the filter";
}

// A reconfiguration built while a load landed is refused likewise; the parameters in effect stay, and
// reconfigure() shows them.
TEST_F(RecognizerRosTest, AReconfigurationIsRefusedWhenTheMemoryChangedDuringItsBuild)
{
  auto recognizer = make(dir_.path());
  EXPECT_EQ(step(*recognizer, 0.0), 1);
  amcr::AMCRConfig config = amcr_ros::toConfig(recognizer->params());
  config.num_v_particles = 40;
  config.prototype_size = 96;  // the tables are rebuilt too
  RecognizerRos::PreparedSwap change = recognizer->prepareReconfigure(config, amcr_ros::kReconfigureTables);
  ASSERT_TRUE(change.error.empty()) << change.error;
  ASSERT_TRUE(recognizer->loadPrototypes(dir_.path()).success);  // lands first
  const std::uint32_t version = recognizer->tableVersion();

  EXPECT_EQ(recognizer->commit(change), RecognizerRos::kMemoryChanged);
  EXPECT_EQ(recognizer->params().num_v_particles, 60);
  EXPECT_EQ(recognizer->params().prototype_size, 128);
  EXPECT_EQ(recognizer->tableVersion(), version);
  EXPECT_EQ(step(*recognizer, 0.1), 1);
  EXPECT_EQ(step(*recognizer, 0.2), 2) << "a refused swap restarted the filter";

  EXPECT_EQ(recognizer->reconfigure(config, amcr_ros::kReconfigureTables), "") << "built again, it lands";
  EXPECT_EQ(config.num_v_particles, 40);
  EXPECT_EQ(recognizer->params().prototype_size, 96);
}

// Two loads at once: the second waits for the first and builds on what it swapped in; neither is refused.
TEST_F(RecognizerRosTest, TwoLoadsAtOnceRunOneAfterTheOther)
{
  amcr_test::TempDir other;
  for (ShapeId id : {ShapeId::kArrow, ShapeId::kFlag})
    cv::imwrite(other.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));
  auto recognizer = make(dir_.path(), "none");
  const std::uint32_t version = recognizer->tableVersion();
  amcr::LoadPrototypes::Response first, second;
  std::thread loading([&] { first = recognizer->loadPrototypes(other.path()); });
  second = recognizer->loadPrototypes(dir_.path());
  loading.join();
  EXPECT_TRUE(first.success) << first.message;
  EXPECT_TRUE(second.success) << second.message;
  EXPECT_EQ(recognizer->tableVersion(), version + 2);
}

// The build runs without the frame lock: images are recognized, with the previous memory, while a
// memory loads.
TEST_F(RecognizerRosTest, ImagesAreRecognizedWithThePreviousMemoryWhileAMemoryLoads)
{
  amcr_test::TempDir large;
  for (ShapeId id : amcr_test::allShapes())
    cv::imwrite(large.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));
  for (std::uint64_t seed = 1; seed <= 10; ++seed)
    cv::imwrite(large.file("random_" + std::to_string(seed) + ".png"), amcr_test::drawRandomSilhouette(seed));
  auto recognizer = make(dir_.path(), "none");  // no cache: every table is built
  EXPECT_EQ(memorySize(*recognizer, 0.0), 3u);

  std::atomic<bool> loaded{false};
  amcr::LoadPrototypes::Response response;
  std::thread loading([&] {
    response = recognizer->loadPrototypes(large.path());
    loaded = true;
  });
  int with_the_previous_memory = 0;  // while the load was under way
  for (double t = 0.1; !loaded; t += 0.1)
  {
    RecognizerRos::Frame out;
    ASSERT_TRUE(recognizer->process(frame(t), false, out));
    with_the_previous_memory += out.memory->size() == 3u ? 1 : 0;
  }
  loading.join();
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_GE(with_the_previous_memory, 3) << "images waited for the load";
  EXPECT_EQ(memorySize(*recognizer, 100.0), 15u);
}
}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_recognizer_ros");
  ros::NodeHandle nh;  // keeps the node up between the tests
  ros::AsyncSpinner spinner(1);  // the dynamic_reconfigure service the tests call
  spinner.start();
  return RUN_ALL_TESTS();
}
