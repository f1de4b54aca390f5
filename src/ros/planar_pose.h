// The pose of a recognized planar prototype in the camera frame: what a robot
// needs to act on the object (each Recognition's pose and the object's tf frame).
// The prototype lies on z = 0 of its own frame: origin at the centre of the
// shape's bounding box in the prototype image, x right and y down along the
// prototype image, z into the target (away from a camera that sees its front);
// metres = prototype pixels * metres_per_pixel. Four points around the shape,
// mapped into the input by the fitted prototype->image homography (a
// perspective view gives a better pose that way; the affine's lift when the
// homography is not used), give four point pairs; cv::solvePnP with
// SOLVEPNP_IPPE (planar targets) solves for the pose.
//
// The camera comes from image_geometry's PinholeCameraModel: a raw image is
// seen through K and the distortion D; a rectified one (image_proc's
// image_rect) through the left 3x3 of P, undistorted (applying D there would
// distort it twice). The pose of a rectified image is in the rectified frame
// (the camera frame for a monocular camera, whose R is the identity).
#pragma once

#include <array>
#include <string>

#include <geometry_msgs/Pose.h>
#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>

#include "amcr/base/affine.h"
#include "amcr/base/homography.h"
#include "amcr/memory/prototype.h"

namespace amcr_ros
{
/// Where a prototype's plane is measured: four points around the shape and the pose's origin,
/// prototype px (of the original image file), and the metric size of a prototype pixel.
struct PlanarTarget
{
  std::array<cv::Point2d, 4> corners;  ///< a rectangle around the shape, in order round it
  cv::Point2d origin;                  ///< the centre of the shape's bounding box
  double metres_per_pixel = 0.0;
};

/// The target of a prototype: its table's corners (the shape's bounding box and a margin) and the
/// box's centre, in the original image's px.
PlanarTarget planarTarget(const amcr::Prototype& prototype, double metres_per_pixel);

/// The target of a whole `width` x `height` prototype image whose shape fills it: its corners and centre.
PlanarTarget imageTarget(int width, int height, double metres_per_pixel);

/// The camera PnP sees the image through.
struct PnpCamera
{
  cv::Matx33d matrix = cv::Matx33d::eye();
  cv::Mat distortion;  ///< empty: none
};

/// Empty when `info` can be used for PnP on raw images, otherwise why not (zeros in K, ...).
std::string checkCameraInfo(const sensor_msgs::CameraInfo& info);

/// The camera of `info` for raw (K, D) or `rectified` (P, no distortion) images, through
/// image_geometry::PinholeCameraModel. False (and `why`) when `info` cannot be used. Never throws.
bool pnpCamera(const sensor_msgs::CameraInfo& info, bool rectified, PnpCamera& camera, std::string& why);

/// Solves the pose; false (and `why`) when it cannot be found (also when a
/// corner maps beyond the horizon). Never throws.
bool planarPose(const amcr::Homography& prototype_to_image, const PlanarTarget& target, const PnpCamera& camera,
                geometry_msgs::Pose& pose, std::string& why);

/// The same from an affine (its lift).
bool planarPose(const amcr::Affine& prototype_to_image, const PlanarTarget& target, const PnpCamera& camera,
                geometry_msgs::Pose& pose, std::string& why);
}  // namespace amcr_ros
