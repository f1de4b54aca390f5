// amcr/Recognitions -> RViz markers: each posed object's outline in its plane and a label, and the
// deletes for objects that lost their pose or their track. A plain function, no ROS node needed:
// used by the nodelet and testable on its own.
#pragma once

#include <cstdint>
#include <vector>

#include <geometry_msgs/Point.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/MarkerArray.h>

#include <amcr/Recognitions.h>

namespace amcr_ros
{
/// The markers of one Recognitions message, in this order: a DELETEALL when `restarted` (the recognizer
/// restarted since the last call); then per entry of recognitions.objects either its two markers or, when it has
/// no pose (pose_valid false or an empty outline), a DELETE of both; then a DELETE of both per entry of
/// recognitions.lost.
///
/// outlines[i]: the outline of recognitions.objects[i] in that object's plane frame (the frame of
/// Recognition.pose: origin at the centre of the shape's bounding box, x right and y down along the prototype
/// image, z into the target; metres), closed or not; empty when the object has no pose. Missing entries count as
/// empty, extra ones are ignored.
///
/// An object's two markers, both with id = track_id, in recognitions.header's frame and stamp, lifetime 0 (they
/// stay until deleted), not frame-locked:
/// - namespace "outline": a LINE_STRIP with pose = Recognition.pose and the outline's points (so they stay in
///   the plane frame), closed (the first point repeated at the end unless it is already there); the line width
///   1.5 % of the larger side of the outline's bounding box, at least 1 mm; opaque, in trackColor(track_id).
/// - namespace "label": a white TEXT_VIEW_FACING "<label> #<track_id>", with " (tentative)" appended while
///   TENTATIVE; its height 20 % of the larger side, at least 1 cm. Placed above the outline: in the plane frame at x = the
///   bounding box's centre, y = one text height above the box's top edge (y is down), z = one text height
///   towards the camera (-z), then mapped into the camera frame by the pose (orientation identity).
visualization_msgs::MarkerArray objectMarkers(const amcr::Recognitions& recognitions,
                                              const std::vector<std::vector<geometry_msgs::Point>>& outlines,
                                              bool restarted);

/// The colour of a track's outline: hue steps of the golden ratio's conjugate per track id (neighbouring ids far
/// apart on the hue wheel), saturation 0.85, value 1, alpha 1. Deterministic.
std_msgs::ColorRGBA trackColor(std::int32_t track_id);
}  // namespace amcr_ros
