// amcr/RecognizerNodelet: Radial-AMCR on an image stream (model: robot_localization's
// ekf_localization_nodelet). It wires two ROS-aware parts to the topics:
//   RecognizerRos (recognizer_ros.h): parameters, memory, recognizer, ~reset, ~load_prototypes,
//     ~teach, ~remove_prototype, dynamic_reconfigure, /diagnostics, the latched ~prototypes table;
//   ObjectPoses (object_poses.h): camera_info, ~metres_per_pixel, the planar pose and tf2 frames;
// and draws the RViz markers (object_markers.h).
//
// Every name is relative: in <group ns="left"> the node reads left/camera/image_raw and publishes
// under /left/amcr, so two recognizers run side by side.
// Subscribes: image (sensor_msgs/Image, through image_transport; ~image_transport picks the transport),
//             camera_info (sensor_msgs/CameraInfo), for the pose: the image's sibling topic unless
//             remapped.
// Publishes:  ~recognitions (amcr/Recognitions), ~overlay (sensor_msgs/Image bgr8, drawn only while
//             subscribed), ~markers (visualization_msgs/MarkerArray: outlines and labels of the
//             objects whose pose is known, deleted when they are lost), ~prototypes
//             (amcr/PrototypeTable, latched).
// Services:   ~reset (std_srvs/Trigger), ~load_prototypes (amcr/LoadPrototypes), ~teach
//             (amcr/TeachPrototype), ~remove_prototype (amcr/RemovePrototype).
//             tf2 frames <~frame_prefix><label>_<track_id>, children of the image's frame, for every object
//             whose pose is known (camera_info and ~metres_per_pixel); /diagnostics (the recognizer:
//             processing time, skipped frames, overlays drawn, converged V-particles, leading
//             hypotheses; the input images: rate and delay, diagnostic_updater's standard keys).
// Parameters: ~prototypes (directory), ~config (YAML file), every key of config/amcr.yaml,
//             ~queue_size (images queued, default 1: live; bags want more),
//             ~metres_per_pixel (one number, or a map label -> number), ~frame_prefix (default: the
//             node's namespace and name, amcr/ for /amcr), ~rectified (default: from the image
//             topic's name), ~min_input_rate, ~max_input_rate (Hz).
//             The filter's tunables are live through dynamic_reconfigure (cfg/AMCR.cfg): a change
//             rebuilds the filter beside the running one, which answers the images until the swap;
//             the subscription stays.
//
// No callback throws: bad input is reported (throttled) and skipped.
#pragma once

#include <memory>

#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>

#include "object_poses.h"
#include "recognizer_ros.h"

namespace amcr_ros
{
class RecognizerNodelet : public nodelet::Nodelet
{
private:
  void onInit() override;
  void imageCb(const sensor_msgs::ImageConstPtr& msg);

  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Publisher pub_overlay_;
  ros::Publisher pub_recognitions_, pub_markers_;
  std::unique_ptr<RecognizerRos> recognizer_;
  std::unique_ptr<ObjectPoses> poses_;
  image_transport::Subscriber sub_image_;  // last: its callback uses everything above
};
}  // namespace amcr_ros
