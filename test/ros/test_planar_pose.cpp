// planarPose on exact inputs: a prototype on a plane parallel to the image at a
// known depth, seen through a pinhole camera, is an exact similarity in the
// image; the pose must come back whatever form D takes (empty, plumb_bob zeros).
#include <cmath>

#include <gtest/gtest.h>

#include "planar_pose.h"

namespace
{
sensor_msgs::CameraInfo camera(double focal, std::vector<double> d)
{
  sensor_msgs::CameraInfo info;
  info.width = 640;
  info.height = 480;
  info.K = {focal, 0, 319.5, 0, focal, 239.5, 0, 0, 1};
  info.D = std::move(d);
  return info;
}

// Prototype px -> image px for a plane at depth z, rotated by `angle` about the optical axis, with
// prototype pixel (0, 0) at camera (x0, y0, z); m/px = mpp.
amcr::Affine similarity(double focal, double mpp, double x0, double y0, double z, double angle)
{
  const double s = focal * mpp / z, c = std::cos(angle), n = std::sin(angle);
  return amcr::Affine(s * c, -s * n, 319.5 + focal * x0 / z, s * n, s * c, 239.5 + focal * y0 / z);
}

TEST(PlanarPose, FrontoParallelPlaneWithAnyDistortionVector)
{
  const double focal = 500, mpp = 0.001, x0 = -0.05, y0 = 0.02, z = 0.6, angle = 0.3;
  for (const std::vector<double>& d : {std::vector<double>{}, std::vector<double>{0, 0, 0, 0, 0}})
  {
    geometry_msgs::Pose pose;
    std::string why;
    ASSERT_TRUE(amcr_ros::planarPose(similarity(focal, mpp, x0, y0, z, angle), 200, 200, mpp, camera(focal, d), pose,
                                     why))
        << "D of size " << d.size() << ": " << why;
    EXPECT_NEAR(pose.position.x, x0, 1e-6);
    EXPECT_NEAR(pose.position.y, y0, 1e-6);
    EXPECT_NEAR(pose.position.z, z, 1e-6);
    // A rotation about z by `angle`: quaternion (0, 0, sin(angle/2), cos(angle/2)), up to sign.
    EXPECT_NEAR(std::abs(pose.orientation.z), std::sin(angle / 2), 1e-6);
    EXPECT_NEAR(std::abs(pose.orientation.w), std::cos(angle / 2), 1e-6);
  }
}

TEST(PlanarPose, RefusesZerosInKAndNoMetricSize)
{
  geometry_msgs::Pose pose;
  std::string why;
  const amcr::Affine a = similarity(500, 0.001, 0, 0, 0.5, 0);
  EXPECT_FALSE(amcr_ros::planarPose(a, 200, 200, 0.001, camera(0.0, {}), pose, why));
  EXPECT_NE(why.find("zeros in K"), std::string::npos) << why;
  EXPECT_FALSE(amcr_ros::planarPose(a, 200, 200, 0.0, camera(500, {}), pose, why));
  EXPECT_NE(why.find("metric size"), std::string::npos) << why;
}
}  // namespace
