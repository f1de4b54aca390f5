// planarPose on exact inputs: a prototype on a plane parallel to the image at a
// known depth, seen through a pinhole camera, is an exact similarity in the
// image; the pose must come back whatever form D takes (empty, plumb_bob zeros).
#include <algorithm>
#include <cmath>
#include <vector>

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

// A plane tilted by 50 degrees about its x axis, 0.5 m away, seen through a
// 500 px camera: an exact homography. Its pose comes back from the
// homography's corners; the best affine over the same corners (what the
// pose used before the homography) misses the tilt by about a degree.
TEST(PlanarPose, TiltedPlaneFromItsHomography)
{
  const double focal = 500, mpp = 0.001, z = 0.5, tilt = 50.0 * M_PI / 180.0;
  const int size = 200;
  // Prototype px -> camera: X = mpp (x - 99.5), Y = mpp (y - 99.5) on the plane, rotated about x, at depth z.
  const cv::Matx33d rotation(1, 0, 0, 0, std::cos(tilt), -std::sin(tilt), 0, std::sin(tilt), std::cos(tilt));
  const cv::Matx33d to_plane(mpp, 0, -mpp * 99.5, 0, mpp, -mpp * 99.5, 0, 0, 1);
  const cv::Matx33d extrinsic(rotation(0, 0), rotation(0, 1), 0, rotation(1, 0), rotation(1, 1), 0, rotation(2, 0),
                              rotation(2, 1), z);
  const cv::Matx33d k(focal, 0, 319.5, 0, focal, 239.5, 0, 0, 1);
  amcr::Homography h = k * extrinsic * to_plane;
  ASSERT_TRUE(amcr::normalizeHomography(h, h));
  // The truth: the origin (prototype pixel (0, 0)) and the rotation's quaternion about x.
  const cv::Vec3d origin = rotation * cv::Vec3d(-mpp * 99.5, -mpp * 99.5, 0) + cv::Vec3d(0, 0, z);

  geometry_msgs::Pose pose;
  std::string why;
  ASSERT_TRUE(amcr_ros::planarPose(h, size, size, mpp, camera(focal, {}), pose, why)) << why;
  EXPECT_NEAR(pose.position.x, origin[0], 1e-6);
  EXPECT_NEAR(pose.position.y, origin[1], 1e-6);
  EXPECT_NEAR(pose.position.z, origin[2], 1e-6);
  EXPECT_NEAR(std::abs(pose.orientation.x), std::sin(tilt / 2), 1e-6);
  EXPECT_NEAR(std::abs(pose.orientation.w), std::cos(tilt / 2), 1e-6);

  // The least-squares affine of the four corners: its pose misses the tilt (by 1.1 degrees).
  std::vector<cv::Point2d> corners = {{0, 0}, {size - 1.0, 0}, {size - 1.0, size - 1.0}, {0, size - 1.0}}, mapped;
  for (const auto& c : corners)
    mapped.push_back(amcr::applyHomography(h, c));
  amcr::Affine affine;
  ASSERT_TRUE(amcr::fitAffine(corners, mapped, affine));
  geometry_msgs::Pose affine_pose;
  ASSERT_TRUE(amcr_ros::planarPose(affine, size, size, mpp, camera(focal, {}), affine_pose, why)) << why;
  const double affine_tilt = 2.0 * std::asin(std::min(1.0, std::abs(affine_pose.orientation.x)));
  EXPECT_GT(std::abs(affine_tilt - tilt), 0.5 * M_PI / 180.0) << "the affine's pose is as good: the test shows nothing";
}

TEST(PlanarPose, RefusesACornerBeyondTheHorizon)
{
  geometry_msgs::Pose pose;
  std::string why;
  // w = 1 - 0.01 x is negative at x = 199.
  EXPECT_FALSE(amcr_ros::planarPose(amcr::Homography(1, 0, 0, 0, 1, 0, -0.01, 0, 1), 200, 200, 0.001,
                                    camera(500, {}), pose, why));
  EXPECT_NE(why.find("horizon"), std::string::npos) << why;
}
}  // namespace
