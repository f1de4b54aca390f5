// The pose and tf part of the nodelet: the metric pose of each recognized
// object (planar_pose.h) from the core's prototype->image homography, the
// camera_info and ~metres_per_pixel, a tf2 frame per object, and each
// object's outline in its own plane (for the RViz markers).
//
// Parameters (private): ~metres_per_pixel (one number, or a map label -> number; m per prototype px),
//                       ~frame_prefix (default: the node's name and namespace, "amcr/" for /amcr,
//                       "left/amcr/" for /left/amcr), ~rectified (bool; unset: true when the image
//                       topic's last name starts with image_rect, as image_proc names it).
// Subscribes:           camera_info (sensor_msgs/CameraInfo): the sibling of the image topic
//                       (/camera/color/image_raw -> /camera/color/camera_info, as image_transport's
//                       camera subscriber does), or where `camera_info` is remapped to.
// Broadcasts:           <~frame_prefix><label>_<track_id>, a child of the image's frame, for every object
//                       whose pose is known.
// Thread-safe; never throws from a callback.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <geometry_msgs/Point.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/transform_broadcaster.h>

#include "amcr/extraction/recognition_result.h"
#include "amcr/memory/prototype_memory.h"
#include "planar_pose.h"
#include "report_throttle.h"
#include <amcr/Recognitions.h>

namespace amcr_ros
{
class ObjectPoses
{
public:
  /// Reads the parameters of `private_nh` (bad values are logged: no poses) and subscribes to
  /// the camera_info of `image_topic` (resolved) on `nh`.
  ObjectPoses(ros::NodeHandle nh, const ros::NodeHandle& private_nh, const std::string& image_topic);

  /// Each object's outline in its own plane (the frame of its pose), metres; empty without a pose.
  using PlaneOutlines = std::vector<std::vector<geometry_msgs::Point>>;

  /// Fills the pose of every object of `out` from the core object at the same index of `objects`
  /// (the message keeps the core's order) and broadcasts its frame. `memory` gives the prototypes'
  /// sizes. An object without a pose keeps pose_valid false; why is logged (throttled). When
  /// `outlines` is given, it gets one entry per object of `out`.
  void fill(const std::vector<amcr::RecognizedObject>& objects, const amcr::PrototypeMemory& memory,
            amcr::Recognitions& out, PlaneOutlines* outlines = nullptr);

private:
  void loadParameters(const ros::NodeHandle& private_nh, const std::string& image_topic);
  void cameraInfoCb(const sensor_msgs::CameraInfoConstPtr& msg);
  /// Metric size of a prototype pixel for `label`, 0 when unknown.
  double metresPerPixel(const std::string& label) const;
  /// The prototype's outline in the plane of `target`'s pose, metres.
  static std::vector<geometry_msgs::Point> planeOutline(const amcr::Prototype& prototype, const PlanarTarget& target);
  /// Broadcasts the frame of `object` (pose_valid).
  void broadcast(const std_msgs::Header& header, const amcr::Recognition& object);

  // Set by the constructor, then read only.
  double metres_per_pixel_ = 0.0;
  std::map<std::string, double> metres_per_pixel_by_label_;
  std::string frame_prefix_;
  bool rectified_ = false;
  std::string camera_info_topic_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  std::mutex mutex_;  // the two below
  std::shared_ptr<const PnpCamera> camera_;  // null until a usable camera_info arrives
  ReportThrottle info_errors_{5.0};  // per problem text, seconds

  ros::Subscriber sub_info_;  // last: its callback uses the members above
};
}  // namespace amcr_ros
