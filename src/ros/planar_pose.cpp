#include "planar_pose.h"

#include <cmath>
#include <vector>

#include <image_geometry/pinhole_camera_model.h>
#include <opencv2/calib3d.hpp>
#include <sensor_msgs/distortion_models.h>
#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>

namespace amcr_ros
{
PlanarTarget planarTarget(const amcr::Prototype& prototype, double metres_per_pixel)
{
  const cv::Matx23d& to_original = prototype.tableToOriginal();
  const double right = prototype.width() - 1.0, bottom = prototype.height() - 1.0;
  PlanarTarget target;
  target.corners = {amcr::applyAffine(to_original, {0.0, 0.0}), amcr::applyAffine(to_original, {right, 0.0}),
                    amcr::applyAffine(to_original, {right, bottom}),
                    amcr::applyAffine(to_original, {0.0, bottom})};
  // The table is centred on the shape's box.
  target.origin = amcr::applyAffine(to_original, prototype.centre());
  target.metres_per_pixel = metres_per_pixel;
  return target;
}

PlanarTarget imageTarget(int width, int height, double metres_per_pixel)
{
  PlanarTarget target;
  const double right = width - 1.0, bottom = height - 1.0;
  target.corners = {cv::Point2d(0.0, 0.0), cv::Point2d(right, 0.0), cv::Point2d(right, bottom),
                    cv::Point2d(0.0, bottom)};
  target.origin = cv::Point2d(0.5 * right, 0.5 * bottom);
  target.metres_per_pixel = metres_per_pixel;
  return target;
}

std::string checkCameraInfo(const sensor_msgs::CameraInfo& info)
{
  const auto& k = info.K;
  for (double v : k)
    if (!std::isfinite(v))
      return "camera_info has a non-finite value in K";
  if (k[0] <= 0.0 || k[4] <= 0.0 || k[8] == 0.0)
    return "camera_info has zeros in K (fx = " + std::to_string(k[0]) + ", fy = " + std::to_string(k[4]) +
           "): the camera is not calibrated";
  for (double v : info.D)
    if (!std::isfinite(v))
      return "camera_info has a non-finite distortion coefficient";
  return "";
}

bool pnpCamera(const sensor_msgs::CameraInfo& info, bool rectified, PnpCamera& camera, std::string& why)
{
  try
  {
    why = checkCameraInfo(info);
    if (!why.empty())
      return false;
    image_geometry::PinholeCameraModel model;
    model.fromCameraInfo(info);
    if (rectified)
    {
      const cv::Matx34d p = model.projectionMatrix();
      const cv::Matx33d matrix(p(0, 0), p(0, 1), p(0, 2), p(1, 0), p(1, 1), p(1, 2), p(2, 0), p(2, 1), p(2, 2));
      if (!cv::checkRange(matrix) || !(matrix(0, 0) > 0.0) || !(matrix(1, 1) > 0.0))
      {
        why = "camera_info has zeros in P (fx' = " + std::to_string(p(0, 0)) +
              "): a rectified image needs the rectified camera's projection";
        return false;
      }
      camera.matrix = matrix;
      camera.distortion.release();  // a rectified image is undistorted already
      return true;
    }
    const std::string& model_name = info.distortion_model;
    if (!info.D.empty() && !model_name.empty() && model_name != sensor_msgs::distortion_models::PLUMB_BOB &&
        model_name != sensor_msgs::distortion_models::RATIONAL_POLYNOMIAL)
    {
      why = "camera_info's distortion model '" + model_name +
            "' is not one PnP applies to raw images: feed the rectified image (image_proc's image_rect) and set "
            "~rectified true";
      return false;
    }
    camera.matrix = model.intrinsicMatrix();
    camera.distortion.release();
    const cv::Mat_<double>& d = model.distortionCoeffs();
    if (!d.empty() && cv::countNonZero(d != 0.0) > 0)
      camera.distortion = cv::Mat(d).reshape(1, 1).clone();
    return true;
  }
  catch (const std::exception& e)
  {
    why = std::string("camera_info cannot be used: ") + e.what();
    return false;
  }
}

bool planarPose(const amcr::Affine& a, const PlanarTarget& target, const PnpCamera& camera, geometry_msgs::Pose& pose,
                std::string& why)
{
  return planarPose(amcr::liftAffine(a), target, camera, pose, why);
}

bool planarPose(const amcr::Homography& h, const PlanarTarget& target, const PnpCamera& camera,
                geometry_msgs::Pose& pose, std::string& why)
{
  try
  {
    const double mpp = target.metres_per_pixel;
    const double extent = cv::norm(target.corners[2] - target.corners[0]);
    if (!(mpp > 0.0) || !(extent >= 2.0))
    {
      why = "no metric size of the prototype";
      return false;
    }
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const cv::Point2d& c : target.corners)
    {
      object.emplace_back((c.x - target.origin.x) * mpp, (c.y - target.origin.y) * mpp, 0.0);
      image.push_back(amcr::applyHomography(h, c));
      if (!std::isfinite(image.back().x) || !std::isfinite(image.back().y))
      {
        why = "the homography maps a corner of the prototype beyond the horizon";
        return false;
      }
    }
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(object, image, camera.matrix, camera.distortion, rvec, tvec, false, cv::SOLVEPNP_IPPE))
    {
      why = "solvePnP found no pose";
      return false;
    }
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    const tf2::Matrix3x3 m(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
    tf2::Quaternion q;
    m.getRotation(q);
    pose.position.x = tvec.at<double>(0);
    pose.position.y = tvec.at<double>(1);
    pose.position.z = tvec.at<double>(2);
    pose.orientation.x = q.x();
    pose.orientation.y = q.y();
    pose.orientation.z = q.z();
    pose.orientation.w = q.w();
    if (!(pose.position.z > 0.0) || !std::isfinite(pose.position.z))
    {
      why = "the pose puts the object behind the camera";
      return false;
    }
    return true;
  }
  catch (const std::exception& e)
  {
    why = std::string("pose failed: ") + e.what();
    return false;
  }
}
}  // namespace amcr_ros
