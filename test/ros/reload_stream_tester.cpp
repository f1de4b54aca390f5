// rostest: ~load_prototypes during a steady image stream must not stall the
// output. The tester draws a memory of 3 prototypes and one of 70 (test/scene_drawing.h)
// into temp directories, loads the small one, streams frames of a flag (only
// in the large memory) at ~rate Hz, measures the output rate over a window
// before the reload, then loads the large memory while the stream goes on and
// measures the output rate while the call is under way. The rate during the
// reload must stay within ~tolerance of the rate before it, and the answers
// after the swap must come from the new memory (its table version; the flag).
//
// Private parameters:
//   ~node        namespace of the nodelet under test (default /amcr)
//   ~image       topic the nodelet subscribes to (default /camera/image)
//   ~rate        input frames per second (default 12)
//   ~prototypes  prototypes of the large memory (default 70)
//   ~baseline    seconds of the window before the reload (default 6)
//   ~min_reload  the reload must take at least this long, s, or the test proves nothing (default 1)
//   ~tolerance   largest relative change of the output rate during the reload (default 0.1)
//   ~timeout     seconds to wait for any one answer (default 60)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <amcr/LoadPrototypes.h>
#include <amcr/PrototypeTable.h>
#include <amcr/Recognitions.h>

#include "../scene_drawing.h"

namespace
{
using amcr_test::ShapeId;
using Clock = std::chrono::steady_clock;

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

/// Every answer of ~recognitions: when it arrived, its table version and whether it reported a label.
class AnswerLog
{
public:
  struct Answer
  {
    Clock::time_point received;
    std::uint32_t table_version = 0;
    bool flag = false;
  };

  void subscribe(ros::NodeHandle& nh, const std::string& topic)
  {
    sub_ = nh.subscribe<amcr::Recognitions>(topic, 100, [this](const amcr::RecognitionsConstPtr& msg) {
      Answer answer{Clock::now(), msg->prototype_table_version, false};
      for (const amcr::Recognition& object : msg->objects)
        answer.flag = answer.flag || object.label == "flag";
      std::lock_guard<std::mutex> lock(mutex_);
      answers_.push_back(answer);
    });
  }

  /// The answers received in [from, to).
  std::vector<Answer> between(Clock::time_point from, Clock::time_point to) const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Answer> out;
    for (const Answer& a : answers_)
      if (a.received >= from && a.received < to)
        out.push_back(a);
    return out;
  }

  std::size_t count() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return answers_.size();
  }

private:
  ros::Subscriber sub_;
  mutable std::mutex mutex_;
  std::vector<Answer> answers_;
};

/// Publishes the frames round and round at a steady rate (never in bursts to catch up), stamped now.
class SteadyStream
{
public:
  SteadyStream(ros::Publisher publisher, std::vector<cv::Mat> frames, double rate)
    : publisher_(std::move(publisher)), frames_(std::move(frames)), period_(std::chrono::duration_cast<Clock::duration>(
                                                                        std::chrono::duration<double>(1.0 / rate)))
  {
    thread_ = std::thread([this] { run(); });
  }
  ~SteadyStream()
  {
    stop_ = true;
    thread_.join();
  }

private:
  void run()
  {
    Clock::time_point next = Clock::now();
    for (std::size_t k = 0; !stop_ && ros::ok(); ++k)
    {
      next += period_;
      std::this_thread::sleep_until(next);
      if (Clock::now() > next + period_)
        next = Clock::now();  // fell behind (a loaded machine): go on from now
      std_msgs::Header header;
      header.stamp = ros::Time::now();
      header.frame_id = "camera";
      publisher_.publish(
          cv_bridge::CvImage(header, sensor_msgs::image_encodings::MONO8, frames_[k % frames_.size()]).toImageMsg());
    }
  }

  ros::Publisher publisher_;
  std::vector<cv::Mat> frames_;
  Clock::duration period_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// Writes `count` prototypes into `dir`: the five drawn shapes first (or the first `count` of them),
/// then random silhouettes.
void writePrototypes(const amcr_test::TempDir& dir, int count)
{
  int written = 0;
  for (ShapeId id : amcr_test::allShapes())
    if (written < count)
    {
      cv::imwrite(dir.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));
      ++written;
    }
  for (std::uint64_t seed = 1; written < count; ++seed, ++written)
    cv::imwrite(dir.file("random_" + std::to_string(seed) + ".png"), amcr_test::drawRandomSilhouette(seed));
}

/// Small frames (a modest load per frame) of a flag over clutter, each with its own noise.
std::vector<cv::Mat> flagFrames()
{
  amcr_test::Scene scene;
  scene.size = cv::Size(320, 240);
  scene.objects = {{ShapeId::kFlag,
                    amcr_test::makeAffine(amcr_test::prototypeCentre(), {160.0, 120.0}, 0.3, 0.8, 0.8, 0.0), 35.0}};
  scene.clutter.random_shapes = 3;
  scene.clutter.lines = 4;
  return amcr_test::renderSequence(scene, 24);
}

/// The latched ~prototypes table with `size` prototypes, or none after `timeout` s.
amcr::PrototypeTableConstPtr tableOfSize(const std::string& topic, std::size_t size, double timeout)
{
  const Clock::time_point deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                        std::chrono::duration<double>(timeout));
  while (Clock::now() < deadline && ros::ok())
  {
    // Latched: a fresh subscription gets the current table.
    const auto table = ros::topic::waitForMessage<amcr::PrototypeTable>(topic, ros::Duration(1.0));
    if (table && table->prototypes.size() == size)
      return table;
  }
  return nullptr;
}

TEST(ReloadDuringStream, OutputRateHoldsAndTheNewMemoryAnswers)
{
  ros::NodeHandle nh, pnh("~");
  std::string node, image_topic;
  double rate = 12.0, baseline_s = 6.0, min_reload_s = 1.0, tolerance = 0.1, timeout = 60.0;
  int large = 70;
  pnh.param<std::string>("node", node, "/amcr");
  pnh.param<std::string>("image", image_topic, "/camera/image");
  pnh.param("rate", rate, rate);
  pnh.param("prototypes", large, large);
  pnh.param("baseline", baseline_s, baseline_s);
  pnh.param("min_reload", min_reload_s, min_reload_s);
  pnh.param("tolerance", tolerance, tolerance);
  pnh.param("timeout", timeout, timeout);

  amcr_test::TempDir small_dir, large_dir;
  writePrototypes(small_dir, 3);  // arrow, crescent, star: no flag
  writePrototypes(large_dir, large);
  ASSERT_TRUE(ros::service::waitForService(node + "/load_prototypes", ros::Duration(timeout)));
  amcr::LoadPrototypes load;
  load.request.directory = small_dir.path();
  ASSERT_TRUE(ros::service::call(node + "/load_prototypes", load));
  ASSERT_TRUE(load.response.success) << load.response.message;

  AnswerLog answers;
  answers.subscribe(nh, node + "/recognitions");
  ros::Publisher image_pub = nh.advertise<sensor_msgs::Image>(image_topic, 2);
  const Clock::time_point subscribed_by = Clock::now() + std::chrono::seconds(static_cast<int>(timeout));
  while (image_pub.getNumSubscribers() == 0 && Clock::now() < subscribed_by)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polling a condition, not waiting for a message
  ASSERT_GT(image_pub.getNumSubscribers(), 0u) << "the nodelet did not subscribe to " << image_topic;

  SteadyStream stream(image_pub, flagFrames(), rate);
  const Clock::time_point answered_by = Clock::now() + std::chrono::seconds(static_cast<int>(timeout));
  while (answers.count() == 0 && Clock::now() < answered_by)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_GT(answers.count(), 0u) << "no answer to the stream";
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the first frames seed the filter: not steady yet

  const Clock::time_point before = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(baseline_s));
  const Clock::time_point reload_start = Clock::now();
  load.request.directory = large_dir.path();
  ASSERT_TRUE(ros::service::call(node + "/load_prototypes", load));
  const Clock::time_point reload_end = Clock::now();
  ASSERT_TRUE(load.response.success) << load.response.message;
  EXPECT_EQ(load.response.num_prototypes, large);

  const double reload_s = seconds(reload_end - reload_start);
  const double rate_before = answers.between(before, reload_start).size() / seconds(reload_start - before);
  const std::vector<AnswerLog::Answer> during = answers.between(reload_start, reload_end);
  const double rate_during = during.size() / reload_s;
  std::printf("input %.1f Hz; output %.2f Hz before the reload, %.2f Hz during it (%zu answers in %.2f s, %+.1f %%)\n",
              rate, rate_before, rate_during, during.size(), reload_s,
              100.0 * (rate_during - rate_before) / std::max(rate_before, 1e-9));
  testing::Test::RecordProperty("rate_before_hz", std::to_string(rate_before));
  testing::Test::RecordProperty("rate_during_reload_hz", std::to_string(rate_during));
  testing::Test::RecordProperty("reload_s", std::to_string(reload_s));
  ASSERT_GE(reload_s, min_reload_s) << "the reload of " << large
                                    << " prototypes was too quick to tell a stall from a steady stream";
  ASSERT_GT(rate_before, 0.5 * rate) << "the nodelet did not keep up with the input before the reload";
  EXPECT_LE(std::abs(rate_during - rate_before), tolerance * rate_before)
      << "the output rate changed by more than " << 100.0 * tolerance << " % while the memory was reloaded";

  // After the swap: the new table's version, and the flag (only in the new memory) reported.
  const amcr::PrototypeTableConstPtr table = tableOfSize(node + "/prototypes", static_cast<std::size_t>(large), timeout);
  ASSERT_TRUE(table) << "no table of " << large << " prototypes on " << node << "/prototypes";
  for (const AnswerLog::Answer& a : during)
    EXPECT_NE(a.table_version, table->version) << "an answer during the reload came from the new memory";
  bool new_memory_answers = false, flag_seen = false;
  const Clock::time_point flag_by = Clock::now() + std::chrono::seconds(static_cast<int>(timeout));
  while (!flag_seen && Clock::now() < flag_by)
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (const AnswerLog::Answer& a : answers.between(reload_end, Clock::now()))
    {
      new_memory_answers = new_memory_answers || a.table_version == table->version;
      flag_seen = flag_seen || (a.flag && a.table_version == table->version);
    }
  }
  EXPECT_TRUE(new_memory_answers) << "no answer with the new table's version " << table->version;
  EXPECT_TRUE(flag_seen) << "the flag, only in the new memory, was not reported within " << timeout << " s";
}
}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "reload_stream_tester");
  ros::AsyncSpinner spinner(2);  // the answers arrive while the test waits on a service call
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  return result;
}
