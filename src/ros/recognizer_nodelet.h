// amcr/RecognizerNodelet: Radial-AMCR on an image stream. Thin glue around
// amcr::Recognizer (model: image_proc's rectify nodelet).
//
// Subscribes: image (sensor_msgs/Image, through image_transport; ~image_transport picks the transport).
// Publishes:  ~recognitions (amcr/Recognitions), ~overlay (sensor_msgs/Image bgr8, drawn only while
//             subscribed), ~prototypes (amcr/PrototypeTable, latched).
// Services:   ~reset (std_srvs/Empty), ~load_prototypes (amcr/LoadPrototypes).
//             tf2 frames <~frame_prefix><label>_<track_id>, children of the image's frame, for every object
//             whose pose is known (camera_info and ~metres_per_pixel); /diagnostics (input rate,
//             processing time, dropped and skipped frames, overlays drawn, converged V-particles,
//             leading hypotheses).
// Subscribes: camera_info (sensor_msgs/CameraInfo), for the pose.
// Parameters: ~prototypes (directory), ~config (YAML file), every key of config/amcr.yaml,
//             ~queue_size (images queued, default 1: live; bags want more),
//             ~metres_per_pixel (one number, or a map label -> number), ~frame_prefix (default amcr/).
//             The filter's tunables are live through dynamic_reconfigure (cfg/AMCR.cfg): a change
//             rebuilds the filter under the lock, the subscription stays.
//
// No callback throws: bad input is reported (throttled) and skipped.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_srvs/Empty.h>
#include <boost/thread/recursive_mutex.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <tf2_ros/transform_broadcaster.h>

#include <map>

#include "amcr/params.h"
#include "amcr/prototype_memory.h"
#include "amcr/recognizer.h"
#include "recognizer_stats.h"
#include "report_throttle.h"
#include <amcr/AMCRConfig.h>
#include <amcr/LoadPrototypes.h>
#include <amcr/Recognitions.h>

namespace amcr_ros
{
class RecognizerNodelet : public nodelet::Nodelet
{
private:
  void onInit() override;

  void imageCb(const sensor_msgs::ImageConstPtr& msg);
  void loadPoseParameters();
  void reconfigureCb(amcr::AMCRConfig& config, std::uint32_t level);
  /// The parameters that differ from params_, readable; empty when none (recognizer_mutex_ held).
  std::string getParameterChanges(const amcr::Params& changed) const;
  void cameraInfoCb(const sensor_msgs::CameraInfoConstPtr& msg);
  /// Fills the poses of `out`'s objects and broadcasts their frames.
  void fillPoses(amcr::Recognitions& out);
  /// Metric size of a prototype pixel for `label`, 0 when unknown.
  double metresPerPixel(const std::string& label) const;
  bool resetCb(std_srvs::Empty::Request& request, std_srvs::Empty::Response& response);
  bool loadPrototypesCb(amcr::LoadPrototypes::Request& request, amcr::LoadPrototypes::Response& response);

  /// Loads a memory and swaps it in (recognizer_mutex_ held by the caller).
  /// Returns the error text, empty on success. Never throws.
  std::string loadPrototypes(const std::string& directory);
  void publishPrototypeTable();
  /// An error about an input image, at most every 5 s per distinct text.
  void reportInputError(const std::string& text);

  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_image_;
  image_transport::Publisher pub_overlay_;
  ros::Publisher pub_recognitions_;
  ros::Publisher pub_prototypes_;
  ros::ServiceServer srv_reset_;
  ros::ServiceServer srv_load_;

  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<dynamic_reconfigure::Server<amcr::AMCRConfig>> reconfigure_server_;

  RecognizerStats stats_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diagnostics_timer_;

  std::mutex report_mutex_;
  ReportThrottle input_errors_{5.0};  // per problem text, seconds

  // Pose (set in onInit, then read only).
  double metres_per_pixel_ = 0.0;
  std::map<std::string, double> metres_per_pixel_by_label_;
  std::string frame_prefix_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_broadcaster_;
  ros::Subscriber sub_info_;
  std::mutex info_mutex_;
  sensor_msgs::CameraInfoConstPtr camera_info_;

  std::mutex recognizer_mutex_;  // everything below
  amcr::Params params_;
  std::shared_ptr<const amcr::PrototypeMemory> memory_;
  std::string memory_directory_;
  std::unique_ptr<amcr::Recognizer> recognizer_;  // null while no memory is loaded
  ros::Time last_stamp_;
  cv::Size last_size_;
};
}  // namespace amcr_ros
