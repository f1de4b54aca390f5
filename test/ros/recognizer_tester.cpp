// The generic rostest tester of amcr/RecognizerNodelet (style point 9): one
// program, parameterised by the launch file, with every input drawn in code
// (test/scene_drawing.h). The nodelet under test starts with a prototype
// directory that does not exist; the tester writes the prototypes and loads
// them through ~load_prototypes, then publishes frames of the expected
// prototype under a known affine over clutter, one at a time, each waited for
// on ~recognitions (no sleeps: every wait is on a condition with a timeout).
//
// Private parameters:
//   ~node              namespace of the nodelet under test (default /amcr)
//   ~image             topic the nodelet subscribes to (default /camera/image)
//   ~label             the expected label: one of arrow, crescent, star (default arrow)
//   ~rotation, ~scale_x, ~scale_y, ~shear   the true prototype->image affine (rad, ratios)
//   ~clutter_seed      seed of the drawn clutter (default 1)
//   ~max_frames        frames within which the label must be recognized (default 100)
//   ~corner_tolerance  mean corner error of prototype_to_image, px (default 6)
//   ~timeout           seconds to wait for any one answer (default 20)
//   ~check_pose        publish camera_info (~camera_info topic, fx = fy = ~focal px, centre of the
//                      image) and check the pose and tf frame (default false: then pose_valid must be
//                      false). Needs a similarity (scale_x = scale_y, shear = 0): the scene is then the
//                      exact image of a plane parallel to the image plane, at z = focal * m/px / scale.
//   ~metres_per_pixel  the value the nodelet was given (default 0.001)
//   ~translation_tolerance  of the pose and the tf frame, m (default 0.02)
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <amcr/LoadPrototypes.h>
#include <amcr/PrototypeTable.h>
#include <amcr/Recognitions.h>

#include "../scene_drawing.h"
#include "reconfigure_request.h"

namespace
{
using amcr_test::ShapeId;
namespace enc = sensor_msgs::image_encodings;

/// Messages of one topic, kept for waiting on a condition.
template <class M>
class Inbox
{
public:
  void subscribe(ros::NodeHandle& nh, const std::string& topic, int queue = 100)
  {
    sub_ = nh.subscribe<M>(topic, queue, [this](const boost::shared_ptr<const M>& msg) {
      std::lock_guard<std::mutex> lock(mutex_);
      messages_.push_back(msg);
      if (messages_.size() > 1000)
        messages_.pop_front();
      changed_.notify_all();
    });
  }
  void shutdown() { sub_.shutdown(); }
  std::size_t publishers() const { return sub_.getNumPublishers(); }

  /// The first message (arrived since the last clear) that satisfies `match`, or null after `timeout` s.
  boost::shared_ptr<const M> waitFor(const std::function<bool(const M&)>& match, double timeout)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
    while (true)
    {
      for (const auto& m : messages_)
        if (match(*m))
          return m;
      if (changed_.wait_until(lock, deadline) == std::cv_status::timeout)
        break;
    }
    for (const auto& m : messages_)
      if (match(*m))
        return m;
    return nullptr;
  }
  void clear()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.clear();
  }

private:
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<boost::shared_ptr<const M>> messages_;
};

ShapeId shapeByName(const std::string& name)
{
  for (ShapeId id : amcr_test::allShapes())
    if (amcr_test::shapeName(id) == name)
      return id;
  throw std::invalid_argument("unknown shape '" + name + "'");
}

/// Waits until `condition` holds (polled while callbacks run), false after `timeout` s.
bool waitUntil(const std::function<bool()>& condition, double timeout)
{
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (!condition())
  {
    if (ros::WallTime::now() > deadline || !ros::ok())
      return false;
    ros::WallDuration(0.01).sleep();  // polling interval of the condition, not a wait for a message
  }
  return true;
}

class RecognizerTest : public testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    ros::NodeHandle pnh("~");
    pnh.param<std::string>("node", node_, "/amcr");
    pnh.param<std::string>("image", image_topic_, "/camera/image");
    pnh.param<std::string>("label", label_, "arrow");
    pnh.param("max_frames", max_frames_, 100);
    pnh.param("corner_tolerance", corner_tolerance_, 6.0);
    pnh.param("timeout", timeout_, 20.0);
    double rotation = 0.5, scale_x = 1.1, scale_y = 0.9, shear = 0.15;
    int clutter_seed = 1;
    pnh.param("rotation", rotation, rotation);
    pnh.param("scale_x", scale_x, scale_x);
    pnh.param("scale_y", scale_y, scale_y);
    pnh.param("shear", shear, shear);
    pnh.param("clutter_seed", clutter_seed, clutter_seed);
    pnh.param("check_pose", check_pose_, false);
    pnh.param<std::string>("camera_info", info_topic_, "/camera/camera_info");
    pnh.param("focal", focal_, 500.0);
    pnh.param("metres_per_pixel", metres_per_pixel_, 0.001);
    pnh.param("translation_tolerance", translation_tolerance_, 0.02);
    similarity_ = std::abs(scale_x - scale_y) < 1e-9 && std::abs(shear) < 1e-9;
    scale_ = scale_x;

    truth_ = amcr_test::makeAffine(amcr_test::prototypeCentre(), {320.0, 240.0}, rotation, scale_x, scale_y, shear);
    scene_.size = cv::Size(640, 480);
    scene_.objects = {{shapeByName(label_), truth_, 35.0}};
    scene_.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
    scene_.clutter.seed = static_cast<std::uint64_t>(clutter_seed);
    clean_ = amcr_test::renderClean(scene_);

    dir_ = std::make_unique<amcr_test::TempDir>();
    for (ShapeId id : memoryShapes())
      cv::imwrite(dir_->file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id));

    nh_ = std::make_unique<ros::NodeHandle>();
    image_pub_ = nh_->advertise<sensor_msgs::Image>(image_topic_, 10);
    recognitions_.subscribe(*nh_, node_ + "/recognitions");
    prototypes_.subscribe(*nh_, node_ + "/prototypes");
    log_.subscribe(*nh_, "/rosout", 1000);
    diagnostics_.subscribe(*nh_, "/diagnostics", 100);
    info_pub_ = nh_->advertise<sensor_msgs::CameraInfo>(info_topic_, 1, true);
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, *nh_);  // every node publishes it: no aggregator needed
  }

  static void TearDownTestSuite()
  {
    image_pub_.shutdown();
    info_pub_.shutdown();
    tf_listener_.reset();
    tf_buffer_.reset();
    recognitions_.shutdown();
    prototypes_.shutdown();
    log_.shutdown();
    diagnostics_.shutdown();
    nh_.reset();
    dir_.reset();
  }

  static std::vector<ShapeId> memoryShapes() { return {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}; }

  /// Loads the drawn prototypes once (the first test that needs them).
  static void ensurePrototypes()
  {
    if (loaded_)
      return;
    ASSERT_TRUE(ros::service::waitForService(node_ + "/load_prototypes", ros::Duration(timeout_)));
    amcr::LoadPrototypes srv;
    srv.request.directory = dir_->path();
    ASSERT_TRUE(ros::service::call(node_ + "/load_prototypes", srv));
    ASSERT_TRUE(srv.response.success) << srv.response.message;
    loaded_ = true;
  }

  static bool waitForNodeletSubscription()
  {
    return waitUntil([] { return image_pub_.getNumSubscribers() > 0; }, timeout_);
  }

  /// The next stamp of the normal (forward) stream.
  static ros::Time nextStamp()
  {
    stamp_ += ros::Duration(0.1);
    return stamp_;
  }

  static sensor_msgs::ImagePtr frame(const cv::Mat& image, const std::string& encoding, const ros::Time& stamp)
  {
    std_msgs::Header header;
    header.stamp = stamp;
    header.frame_id = "camera";
    return cv_bridge::CvImage(header, encoding, image).toImageMsg();
  }

  /// A noisy frame of the scene, mono8.
  static cv::Mat sceneFrame()
  {
    return amcr_test::addNoise(clean_, scene_.clutter.noise_sigma, scene_.clutter.seed * 1000 + noise_index_++);
  }

  /// Publishes and waits for the recognitions of that stamp.
  static amcr::RecognitionsConstPtr publishAndWait(const sensor_msgs::ImagePtr& msg)
  {
    const ros::Time stamp = msg->header.stamp;
    image_pub_.publish(msg);
    return recognitions_.waitFor([stamp](const amcr::Recognitions& r) { return r.header.stamp == stamp; }, timeout_);
  }

  /// Waits for a log line of `level` or above from the nodelet that contains `text`.
  static bool waitForLog(std::uint8_t level, const std::string& text)
  {
    return log_.waitFor(
               [&](const rosgraph_msgs::Log& m) {
                 return m.level >= level && m.msg.find(text) != std::string::npos;
               },
               timeout_) != nullptr;
  }

  /// A value of the nodelet's "recognizer" status, or null when `array` has none.
  static const std::string* diagnosticValue(const diagnostic_msgs::DiagnosticArray& array, const std::string& key)
  {
    for (const auto& status : array.status)
      if (status.name.find("recognizer") != std::string::npos)
        for (const auto& kv : status.values)
          if (kv.key == key)
            return &kv.value;
    return nullptr;
  }
  static long diagnosticNumber(const diagnostic_msgs::DiagnosticArray& array, const std::string& key)
  {
    const std::string* v = diagnosticValue(array, key);
    return v ? std::stol(*v) : -1;
  }

  static double cornerError(const amcr::Recognition& object)
  {
    const auto& a = object.prototype_to_image;
    return amcr_test::cornerError(amcr::Affine(a[0], a[1], a[2], a[3], a[4], a[5]), truth_);
  }

  static bool recognizedRight(const amcr::Recognitions& r)
  {
    return !r.objects.empty() && r.objects[0].label == label_ && cornerError(r.objects[0]) <= corner_tolerance_;
  }

  static sensor_msgs::CameraInfo cameraInfo(double focal)
  {
    sensor_msgs::CameraInfo info;
    info.header.frame_id = "camera";
    info.width = static_cast<std::uint32_t>(scene_.size.width);
    info.height = static_cast<std::uint32_t>(scene_.size.height);
    info.distortion_model = "plumb_bob";
    info.D = {0, 0, 0, 0, 0};
    const double cx = 0.5 * (scene_.size.width - 1), cy = 0.5 * (scene_.size.height - 1);
    info.K = {focal, 0, cx, 0, focal, cy, 0, 0, 1};
    info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    info.P = {focal, 0, cx, 0, 0, focal, cy, 0, 0, 0, 1, 0};
    return info;
  }

  static std::string node_, image_topic_, label_, info_topic_;
  static bool check_pose_, similarity_;
  static double focal_, metres_per_pixel_, translation_tolerance_, scale_;
  static ros::Publisher info_pub_;
  static std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  static std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  static int max_frames_;
  static double corner_tolerance_, timeout_;
  static amcr::Affine truth_;
  static amcr_test::Scene scene_;
  static cv::Mat clean_;
  static std::unique_ptr<amcr_test::TempDir> dir_;
  static std::unique_ptr<ros::NodeHandle> nh_;
  static ros::Publisher image_pub_;
  static Inbox<amcr::Recognitions> recognitions_;
  static Inbox<amcr::PrototypeTable> prototypes_;
  static Inbox<rosgraph_msgs::Log> log_;
  static Inbox<diagnostic_msgs::DiagnosticArray> diagnostics_;
  static bool loaded_;
  static ros::Time stamp_;
  static std::uint64_t noise_index_;
};

std::string RecognizerTest::node_, RecognizerTest::image_topic_, RecognizerTest::label_, RecognizerTest::info_topic_;
bool RecognizerTest::check_pose_ = false, RecognizerTest::similarity_ = false;
double RecognizerTest::focal_ = 500.0, RecognizerTest::metres_per_pixel_ = 0.001,
       RecognizerTest::translation_tolerance_ = 0.02, RecognizerTest::scale_ = 1.0;
ros::Publisher RecognizerTest::info_pub_;
std::unique_ptr<tf2_ros::Buffer> RecognizerTest::tf_buffer_;
std::unique_ptr<tf2_ros::TransformListener> RecognizerTest::tf_listener_;
int RecognizerTest::max_frames_ = 100;
double RecognizerTest::corner_tolerance_ = 6.0, RecognizerTest::timeout_ = 20.0;
amcr::Affine RecognizerTest::truth_;
amcr_test::Scene RecognizerTest::scene_;
cv::Mat RecognizerTest::clean_;
std::unique_ptr<amcr_test::TempDir> RecognizerTest::dir_;
std::unique_ptr<ros::NodeHandle> RecognizerTest::nh_;
ros::Publisher RecognizerTest::image_pub_;
Inbox<amcr::Recognitions> RecognizerTest::recognitions_;
Inbox<amcr::PrototypeTable> RecognizerTest::prototypes_;
Inbox<rosgraph_msgs::Log> RecognizerTest::log_;
Inbox<diagnostic_msgs::DiagnosticArray> RecognizerTest::diagnostics_;
bool RecognizerTest::loaded_ = false;
ros::Time RecognizerTest::stamp_(1000.0);
std::uint64_t RecognizerTest::noise_index_ = 0;

// The nodelet was started with a missing prototype directory: it stays up,
// refuses a bad directory with an error text, and takes a good one.
TEST_F(RecognizerTest, StartsWithoutPrototypesAndLoadsThemAtRuntime)
{
  ASSERT_TRUE(ros::service::waitForService(node_ + "/load_prototypes", ros::Duration(timeout_)));
  // Before any memory: the latched table is empty.
  auto empty = prototypes_.waitFor([](const amcr::PrototypeTable& t) { return t.prototypes.empty(); }, timeout_);
  EXPECT_TRUE(empty) << "no empty label table on " << node_ << "/prototypes";

  amcr::LoadPrototypes bad;
  bad.request.directory = dir_->file("no_such_directory");
  ASSERT_TRUE(ros::service::call(node_ + "/load_prototypes", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_NE(bad.response.message.find("no_such_directory"), std::string::npos) << bad.response.message;

  ensurePrototypes();
  auto table = prototypes_.waitFor([](const amcr::PrototypeTable& t) { return t.prototypes.size() == 3; }, timeout_);
  ASSERT_TRUE(table) << "no label table with 3 prototypes on " << node_ << "/prototypes";
  std::vector<std::string> labels;
  for (const auto& p : table->prototypes)
  {
    labels.push_back(p.label);
    EXPECT_EQ(p.width, amcr_test::kPrototypeImageSize);
    EXPECT_EQ(p.height, amcr_test::kPrototypeImageSize);
  }
  EXPECT_NE(std::find(labels.begin(), labels.end(), label_), labels.end());
  EXPECT_EQ(table->directory, dir_->path());
}

// The expected label with the true affine within a bounded number of frames.
TEST_F(RecognizerTest, RecognizesTheShownPrototype)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription()) << "nobody subscribes to " << image_topic_;
  int frames = 0;
  amcr::RecognitionsConstPtr last;
  for (; frames < max_frames_; ++frames)
  {
    last = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
    ASSERT_TRUE(last) << "no recognitions for frame " << frames << " within " << timeout_ << " s";
    EXPECT_EQ(last->header.frame_id, "camera");
    if (recognizedRight(*last))
      break;
  }
  ASSERT_LT(frames, max_frames_) << label_ << " not recognized within " << max_frames_ << " frames";
  const amcr::Recognition& object = last->objects[0];
  EXPECT_GE(object.score, 0.0);
  EXPECT_LE(object.score, 1.0);
  EXPECT_GE(object.support, 1);
  EXPECT_GE(object.track_id, 1);
  EXPECT_FALSE(object.outline.points.empty());
  EXPECT_FALSE(object.correspondences.empty());
  // The view (issue 13): anisotropy >= 1 and its viewing angle; the homography is the affine's lift when not used.
  EXPECT_GE(object.anisotropy, 1.0);
  EXPECT_NEAR(object.viewing_angle_deg, std::acos(1.0 / object.anisotropy) * 180.0 / M_PI, 1e-9);
  EXPECT_EQ(object.homography[8], 1.0);
  if (!object.homography_valid)
  {
    for (std::size_t i = 0; i < 6; ++i)
      EXPECT_DOUBLE_EQ(object.homography[i], object.prototype_to_image[i]) << "homography entry " << i;
  }
  if (!check_pose_)
  {
    EXPECT_FALSE(object.pose_valid) << "a pose without camera_info";
  }
  RecordProperty("frames_to_recognition", frames + 1);
  ROS_INFO("%s recognized after %d frames, corner error %.2f px", label_.c_str(), frames + 1, cornerError(object));
}

// With camera_info and a metric size: the pose and the tf frame match the
// truth. A camera_info with zeros in K is refused first.
TEST_F(RecognizerTest, PoseAndFrameWithCameraInfo)
{
  if (!check_pose_)
    return;  // this configuration checks that no pose comes without camera_info (above)
  ASSERT_TRUE(similarity_) << "~check_pose needs scale_x = scale_y and shear = 0";
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(waitUntil([] { return info_pub_.getNumSubscribers() > 0; }, timeout_))
      << "nobody subscribes to " << info_topic_;
  info_pub_.publish(cameraInfo(0.0));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "zeros in K")) << "no error about a camera_info with zeros in K";
  info_pub_.publish(cameraInfo(focal_));

  // The truth: prototype pixel (0, 0) is the frame's origin; the plane is parallel to the image.
  const double z = focal_ * metres_per_pixel_ / scale_;
  const double cx = 0.5 * (scene_.size.width - 1), cy = 0.5 * (scene_.size.height - 1);
  const cv::Point2d origin(truth_(0, 2), truth_(1, 2));
  const tf2::Vector3 expected((origin.x - cx) * z / focal_, (origin.y - cy) * z / focal_, z);

  // The pose is checked once the object has been recognized with a pose in
  // kSettleFrames frames in a row: the first report of a shape with long arcs
  // (the crescent) can still slide along them, and the tracked fit settles.
  constexpr int kSettleFrames = 5;
  amcr::RecognitionsConstPtr last;
  int frames = 0, in_a_row = 0;
  for (; frames < max_frames_; ++frames)
  {
    last = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
    ASSERT_TRUE(last);
    in_a_row = (recognizedRight(*last) && last->objects[0].pose_valid) ? in_a_row + 1 : 0;
    if (in_a_row >= kSettleFrames)
      break;
  }
  ASSERT_LT(frames, max_frames_) << "no settled pose for " << label_ << " within " << max_frames_ << " frames";
  const amcr::Recognition& object = last->objects[0];
  const tf2::Vector3 position(object.pose.position.x, object.pose.position.y, object.pose.position.z);
  EXPECT_LT((position - expected).length(), translation_tolerance_)
      << "pose (" << position.x() << ", " << position.y() << ", " << position.z() << ") m, truth (" << expected.x()
      << ", " << expected.y() << ", " << expected.z() << ") m";

  const std::string child = "amcr/" + object.label + "_" + std::to_string(object.track_id);
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf_buffer_->lookupTransform("camera", child, last->header.stamp, ros::Duration(timeout_));
  }
  catch (const tf2::TransformException& e)
  {
    FAIL() << "no tf frame " << child << ": " << e.what();
  }
  const tf2::Vector3 tf_position(t.transform.translation.x, t.transform.translation.y, t.transform.translation.z);
  EXPECT_LT((tf_position - expected).length(), translation_tolerance_);
  ROS_INFO("pose of %s: (%.4f, %.4f, %.4f) m, truth (%.4f, %.4f, %.4f) m", child.c_str(), position.x(), position.y(),
           position.z(), expected.x(), expected.y(), expected.z());
}

// ~overlay is drawn while someone subscribes: bgr8, the input's header, and
// wider than the input (the prototype column).
TEST_F(RecognizerTest, OverlayWhileSubscribed)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  Inbox<sensor_msgs::Image> overlay;
  overlay.subscribe(*nh_, node_ + "/overlay", 5);
  ASSERT_TRUE(waitUntil([&] { return overlay.publishers() > 0; }, timeout_));
  // The nodelet learns of the subscriber a moment after we learn of it: a few frames at most.
  sensor_msgs::ImageConstPtr got;
  for (int i = 0; i < 50 && !got; ++i)
  {
    const ros::Time stamp = nextStamp();
    ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, stamp)));
    got = overlay.waitFor([stamp](const sensor_msgs::Image& m) { return m.header.stamp == stamp; }, 0.5);
  }
  ASSERT_TRUE(got) << "no overlay while subscribed";
  EXPECT_EQ(got->encoding, enc::BGR8);
  EXPECT_GT(static_cast<int>(got->width), scene_.size.width);
  EXPECT_GE(static_cast<int>(got->height), scene_.size.height);
  EXPECT_EQ(got->header.frame_id, "camera");
  overlay.shutdown();
}

// /diagnostics reports the stream and the filter; overlays are drawn only
// while someone subscribes to ~overlay (the counter stands still without).
TEST_F(RecognizerTest, DiagnosticsAndNoOverlayWithoutSubscribers)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp())));
  diagnostics_.clear();
  auto idle = diagnostics_.waitFor(
      [](const diagnostic_msgs::DiagnosticArray& a) {
        return diagnosticNumber(a, "overlay subscribers") == 0 && diagnosticNumber(a, "frames processed") > 0;
      },
      timeout_);
  ASSERT_TRUE(idle) << "no diagnostics of the recognizer without overlay subscribers";
  const long processed = diagnosticNumber(*idle, "frames processed");
  const long overlays = diagnosticNumber(*idle, "overlays drawn");
  EXPECT_GT(overlays, 0) << "OverlayWhileSubscribed (run before) drew none";
  EXPECT_EQ(diagnosticNumber(*idle, "prototypes"), 3);
  EXPECT_TRUE(diagnosticValue(*idle, "input rate (Hz)"));
  EXPECT_TRUE(diagnosticValue(*idle, "processing time, mean (ms)"));
  EXPECT_TRUE(diagnosticValue(*idle, "converged V-particles"));
  EXPECT_TRUE(diagnosticValue(*idle, "leading hypotheses"));

  constexpr int kFrames = 5;
  for (int i = 0; i < kFrames; ++i)
    ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp())));
  auto later = diagnostics_.waitFor(
      [&](const diagnostic_msgs::DiagnosticArray& a) { return diagnosticNumber(a, "frames processed") >= processed + kFrames; },
      timeout_);
  ASSERT_TRUE(later) << "frames processed did not grow in /diagnostics";
  EXPECT_EQ(diagnosticNumber(*later, "overlays drawn"), overlays) << "overlays drawn while nobody subscribed";
}

// ~reset restarts the filter: the next frame is iteration 1.
TEST_F(RecognizerTest, ResetRestartsTheFilter)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  auto before = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(before);
  ASSERT_GT(before->iteration, 1);
  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call(node_ + "/reset", empty));
  auto after = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(after);
  EXPECT_EQ(after->iteration, 1);
}

// dynamic_reconfigure: a new particle count rebuilds the filter (iteration 1,
// the new count in /diagnostics); a new table size rebuilds the prototype
// tables; the subscription stays and recognitions keep coming.
TEST_F(RecognizerTest, ReconfigureRebuildsTheFilter)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(ros::service::waitForService(node_ + "/set_parameters", ros::Duration(timeout_)));
  dynamic_reconfigure::Reconfigure srv = amcr_test::intParameterRequest("num_v_particles", 40);
  ASSERT_TRUE(ros::service::call(node_ + "/set_parameters", srv));
  bool echoed = false;
  for (const auto& p : srv.response.config.ints)
    echoed = echoed || (p.name == "num_v_particles" && p.value == 40);
  EXPECT_TRUE(echoed) << "the answer does not carry num_v_particles = 40";

  auto first = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(first) << "no recognitions after reconfiguring";
  EXPECT_EQ(first->iteration, 1);
  diagnostics_.clear();
  auto report = diagnostics_.waitFor(
      [](const diagnostic_msgs::DiagnosticArray& a) {
        const std::string* v = diagnosticValue(a, "converged V-particles");
        return v && v->find("of 40") != std::string::npos;
      },
      timeout_);
  EXPECT_TRUE(report) << "/diagnostics does not show 40 V-particles";

  dynamic_reconfigure::Reconfigure tables = amcr_test::intParameterRequest("prototype_size", 96);
  ASSERT_TRUE(ros::service::call(node_ + "/set_parameters", tables));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::INFO, "prototype tables and filter rebuilt"));
  auto after = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(after) << "no recognitions after rebuilding the tables";
  EXPECT_EQ(after->iteration, 1);
}

// Every bad input: the convertible ones are recognized, the others are
// refused with an error naming the problem; the nodelet keeps answering.
TEST_F(RecognizerTest, BadInputsLeaveTheNodeletAnswering)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  const cv::Mat grey = sceneFrame();
  cv::Mat bgr, bgra, yuv;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  cv::Mat mono16;
  grey.convertTo(mono16, CV_16U, 257.0);
  // yuv422 (UYVY): U Y0 V Y1 per two pixels; grey: U = V = 128.
  yuv.create(grey.rows, grey.cols, CV_8UC2);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x)
      yuv.at<cv::Vec2b>(y, x) = cv::Vec2b(128, grey.at<std::uint8_t>(y, x));

  // Converted: each gives recognitions.
  const std::vector<std::pair<std::string, cv::Mat>> converted = {
      {enc::MONO16, mono16}, {enc::BGRA8, bgra}, {enc::RGB8, bgr}, {enc::BAYER_RGGB8, grey}, {enc::YUV422, yuv}};
  for (const auto& c : converted)
    EXPECT_TRUE(publishAndWait(frame(c.second, c.first, nextStamp()))) << "no recognitions for a " << c.first
                                                                          << " image";

  // Refused: an error naming the problem, no crash.
  cv::Mat depth;
  grey.convertTo(depth, CV_32F, 1.0 / 255.0);
  image_pub_.publish(frame(depth, enc::TYPE_32FC1, nextStamp()));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "32FC1")) << "no error naming 32FC1";

  auto zero = boost::make_shared<sensor_msgs::Image>();
  zero->header.stamp = nextStamp();
  zero->encoding = enc::MONO8;
  image_pub_.publish(zero);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "zero-size")) << "no error about a zero-size image";

  auto short_data = frame(grey, enc::MONO8, nextStamp());
  short_data->data.resize(short_data->data.size() / 2);
  image_pub_.publish(short_data);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "inconsistent image")) << "no error about truncated data";

  // The resolution changes mid-stream: recognized at the new size, and back.
  cv::Mat small;
  cv::resize(grey, small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
  EXPECT_TRUE(publishAndWait(frame(small, enc::MONO8, nextStamp()))) << "no recognitions after a size change";
  EXPECT_TRUE(publishAndWait(frame(grey, enc::MONO8, nextStamp()))) << "no recognitions after the size came back";

  // Time goes backwards (a looped bag): reset and say so.
  auto back = publishAndWait(frame(grey, enc::MONO8, ros::Time(500.0)));
  ASSERT_TRUE(back) << "no recognitions after time went backwards";
  EXPECT_EQ(back->iteration, 1);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::WARN, "time went backwards"));

  // Still answering.
  std_srvs::Empty empty;
  EXPECT_TRUE(ros::service::call(node_ + "/reset", empty));
  EXPECT_TRUE(publishAndWait(frame(grey, enc::MONO8, nextStamp())));
}
}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "recognizer_tester");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
