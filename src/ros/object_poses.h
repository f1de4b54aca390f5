// The pose and tf part of the nodelet: the metric pose of each recognized
// object (planar_pose.h) from the core's prototype->image affine, the
// camera_info and ~metres_per_pixel, and a tf2 frame per object.
//
// Parameters (private): ~metres_per_pixel (one number, or a map label -> number; m per prototype px),
//                       ~frame_prefix (default amcr/).
// Subscribes:           camera_info (sensor_msgs/CameraInfo).
// Broadcasts:           <~frame_prefix><label>_<track_id>, a child of the image's frame, for every object
//                       whose pose is known.
// Thread-safe; never throws from a callback.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <tf2_ros/transform_broadcaster.h>

#include "amcr/prototype_memory.h"
#include "amcr/recognition_result.h"
#include "report_throttle.h"
#include <amcr/Recognitions.h>

namespace amcr_ros
{
class ObjectPoses
{
public:
  /// Reads the parameters of `private_nh` (bad values are logged: no poses) and subscribes to
  /// camera_info on `nh`.
  ObjectPoses(ros::NodeHandle nh, const ros::NodeHandle& private_nh);

  /// Fills the pose of every object of `out` from the core object at the same index of `objects`
  /// (the message keeps the core's order) and broadcasts its frame. `memory` gives the prototypes'
  /// sizes. An object without a pose keeps pose_valid false; why is logged (throttled).
  void fill(const std::vector<amcr::RecognizedObject>& objects, const amcr::PrototypeMemory& memory,
            amcr::Recognitions& out);

private:
  void loadParameters(const ros::NodeHandle& private_nh);
  void cameraInfoCb(const sensor_msgs::CameraInfoConstPtr& msg);
  /// Metric size of a prototype pixel for `label`, 0 when unknown.
  double metresPerPixel(const std::string& label) const;
  /// Broadcasts the frame of `object` (pose_valid).
  void broadcast(const std_msgs::Header& header, const amcr::Recognition& object);

  // Set by the constructor, then read only.
  double metres_per_pixel_ = 0.0;
  std::map<std::string, double> metres_per_pixel_by_label_;
  std::string frame_prefix_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;

  std::mutex mutex_;  // the two below
  sensor_msgs::CameraInfoConstPtr camera_info_;
  ReportThrottle info_errors_{5.0};  // per problem text, seconds

  ros::Subscriber sub_info_;  // last: its callback uses the members above
};
}  // namespace amcr_ros
