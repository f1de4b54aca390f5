// The fixture of the generic rostest tester of amcr/RecognizerNodelet (recognizer_tester.cpp says
// what it checks and its parameters): the parameters read once per program, the drawn scene and
// prototypes, the topics and services of the nodelet under test, and the helpers the tests share.
#pragma once

#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <amcr/LoadPrototypes.h>
#include <amcr/PrototypeTable.h>
#include <amcr/Recognitions.h>

#include "../scene_drawing.h"

namespace recognizer_tester
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

inline ShapeId shapeByName(const std::string& name)
{
  for (ShapeId id : amcr_test::allShapes())
    if (amcr_test::shapeName(id) == name)
      return id;
  throw std::invalid_argument("unknown shape '" + name + "'");
}

/// Waits until `condition` holds (polled while callbacks run), false after `timeout` s.
inline bool waitUntil(const std::function<bool()>& condition, double timeout)
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
    pnh.param("rectified", rectified_, false);
    pnh.param<std::string>("frame_prefix", frame_prefix_, "amcr/");
    pnh.param("check_markers", check_markers_, false);
    pnh.param("check_teach", check_teach_, false);
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

  /// A value of the nodelet's status `name` ("recognizer", "input images"), or null when `array` has none.
  static const std::string* diagnosticValue(const diagnostic_msgs::DiagnosticArray& array, const std::string& key,
                                            const std::string& name = "recognizer")
  {
    for (const auto& status : array.status)
      if (status.name.find(name) != std::string::npos)
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
    if (rectified_)  // the raw camera differs: applying K and D to the rectified frames gives another pose
    {
      info.D = {-0.25, 0.08, 0, 0, 0};
      info.K = {1.12 * focal, 0, cx, 0, 1.12 * focal, cy, 0, 0, 1};
    }
    info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    info.P = {focal, 0, cx, 0, 0, focal, cy, 0, 0, 0, 1, 0};
    return info;
  }

  /// The pose's origin in the prototype image: the centre of the shape's bounding box (as the nodelet
  /// measures it, from the prototype it builds of the same image).
  static cv::Point2d poseOrigin()
  {
    const amcr::Params params;
    const amcr::Prototype prototype(label_, amcr_test::drawPrototype(shapeByName(label_)), params.prototype_size,
                                    params.edge_threshold, params.blur_sigma);
    return amcr::applyAffine(prototype.tableToOriginal(), prototype.centre());
  }

  static std::string node_, image_topic_, label_, info_topic_, frame_prefix_;
  static bool check_pose_, similarity_, rectified_, check_markers_, check_teach_;
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
}  // namespace recognizer_tester
