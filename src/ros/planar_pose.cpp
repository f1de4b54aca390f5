#include "planar_pose.h"

#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>

namespace amcr_ros
{
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

bool planarPose(const amcr::Affine& a, int width, int height, double metres_per_pixel,
                const sensor_msgs::CameraInfo& info, geometry_msgs::Pose& pose, std::string& why)
{
  return planarPose(amcr::liftAffine(a), width, height, metres_per_pixel, info, pose, why);
}

bool planarPose(const amcr::Homography& h, int width, int height, double metres_per_pixel,
                const sensor_msgs::CameraInfo& info, geometry_msgs::Pose& pose, std::string& why)
{
  try
  {
    if (!(metres_per_pixel > 0.0) || width < 2 || height < 2)
    {
      why = "no metric size of the prototype";
      return false;
    }
    why = checkCameraInfo(info);
    if (!why.empty())
      return false;
    const std::vector<cv::Point2d> corners = {
        {0.0, 0.0}, {width - 1.0, 0.0}, {width - 1.0, height - 1.0}, {0.0, height - 1.0}};
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const cv::Point2d& c : corners)
    {
      object.emplace_back(c.x * metres_per_pixel, c.y * metres_per_pixel, 0.0);
      image.push_back(amcr::applyHomography(h, c));
      if (!std::isfinite(image.back().x) || !std::isfinite(image.back().y))
      {
        why = "the homography maps a corner of the prototype beyond the horizon";
        return false;
      }
    }
    const cv::Matx33d k(info.K[0], info.K[1], info.K[2], info.K[3], info.K[4], info.K[5], info.K[6], info.K[7],
                        info.K[8]);
    cv::Mat d;  // empty: no distortion (a camera_info may leave D empty)
    if (!info.D.empty())
      d = cv::Mat(info.D, true).reshape(1, 1);
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(object, image, k, d, rvec, tvec, false, cv::SOLVEPNP_IPPE))
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
