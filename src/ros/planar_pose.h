// The pose of a recognized planar prototype in the camera frame (issue 3, item 3).
// The prototype lies on z = 0 of its own frame: origin at pixel (0, 0) of the
// prototype's original image, x right, y down, metres = pixels * metres_per_pixel.
// The four corners of the prototype image, mapped into the input by the fitted
// prototype->image homography (a perspective view gives a better pose that
// way; the affine's lift when the homography is not used), give four point
// pairs; cv::solvePnP with SOLVEPNP_IPPE (planar targets) solves for the pose.
#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <sensor_msgs/CameraInfo.h>

#include "amcr/affine.h"
#include "amcr/homography.h"

namespace amcr_ros
{
/// Empty when `info` can be used for PnP, otherwise why not (zeros in K, ...).
std::string checkCameraInfo(const sensor_msgs::CameraInfo& info);

/// Solves the pose; false (and `why`) when it cannot be found (also when a
/// corner maps beyond the horizon). Never throws.
bool planarPose(const amcr::Homography& prototype_to_image, int prototype_width, int prototype_height,
                double metres_per_pixel, const sensor_msgs::CameraInfo& info, geometry_msgs::Pose& pose,
                std::string& why);

/// The same from an affine (its lift).
bool planarPose(const amcr::Affine& prototype_to_image, int prototype_width, int prototype_height,
                double metres_per_pixel, const sensor_msgs::CameraInfo& info, geometry_msgs::Pose& pose,
                std::string& why);
}  // namespace amcr_ros
