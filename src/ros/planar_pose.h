// The pose of a recognized planar prototype in the camera frame (issue 3, item 3).
// The prototype lies on z = 0 of its own frame: origin at pixel (0, 0) of the
// prototype's original image, x right, y down, metres = pixels * metres_per_pixel.
// The four corners of the prototype image, mapped into the input by the fitted
// prototype->image affine (the least-squares summary of the correspondences),
// give four point pairs; cv::solvePnP with SOLVEPNP_IPPE (planar targets)
// solves for the pose.
#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <sensor_msgs/CameraInfo.h>

#include "amcr/affine.h"

namespace amcr_ros
{
/// Empty when `info` can be used for PnP, otherwise why not (zeros in K, ...).
std::string checkCameraInfo(const sensor_msgs::CameraInfo& info);

/// Solves the pose; false (and `why`) when it cannot be found. Never throws.
bool planarPose(const amcr::Affine& prototype_to_image, int prototype_width, int prototype_height,
                double metres_per_pixel, const sensor_msgs::CameraInfo& info, geometry_msgs::Pose& pose,
                std::string& why);
}  // namespace amcr_ros
