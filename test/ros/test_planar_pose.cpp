// planarPose on exact inputs: a prototype on a plane parallel to the image at a
// known depth, seen through a pinhole camera, is an exact similarity in the
// image; the pose must come back whatever form D takes (empty, plumb_bob
// zeros), for raw and rectified images (the camera of image_geometry's model),
// with its origin at the centre of the shape's bounding box.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "planar_pose.h"

namespace
{
sensor_msgs::CameraInfo cameraInfo(double focal, std::vector<double> d)
{
  sensor_msgs::CameraInfo info;
  info.width = 640;
  info.height = 480;
  info.distortion_model = "plumb_bob";
  info.K = {focal, 0, 319.5, 0, focal, 239.5, 0, 0, 1};
  info.D = std::move(d);
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {focal, 0, 319.5, 0, 0, focal, 239.5, 0, 0, 0, 1, 0};
  return info;
}

amcr_ros::PnpCamera camera(double focal, std::vector<double> d = {})
{
  amcr_ros::PnpCamera c;
  std::string why;
  EXPECT_TRUE(amcr_ros::pnpCamera(cameraInfo(focal, std::move(d)), false, c, why)) << why;
  return c;
}

// Prototype px -> image px for a plane at depth z, rotated by `angle` about the optical axis, with
// the target's origin (the centre of a 200 x 200 image, (99.5, 99.5)) at camera (x0, y0, z); m/px = mpp.
amcr::Affine similarity(double focal, double mpp, double x0, double y0, double z, double angle)
{
  const double s = focal * mpp / z, c = std::cos(angle), n = std::sin(angle), o = 99.5;
  return amcr::Affine(s * c, -s * n, 319.5 + focal * x0 / z - s * (c * o - n * o), s * n, s * c,
                      239.5 + focal * y0 / z - s * (n * o + c * o));
}

TEST(PlanarPose, FrontoParallelPlaneWithAnyDistortionVector)
{
  const double focal = 500, mpp = 0.001, x0 = -0.05, y0 = 0.02, z = 0.6, angle = 0.3;
  for (const std::vector<double>& d : {std::vector<double>{}, std::vector<double>{0, 0, 0, 0, 0}})
  {
    geometry_msgs::Pose pose;
    std::string why;
    ASSERT_TRUE(amcr_ros::planarPose(similarity(focal, mpp, x0, y0, z, angle), amcr_ros::imageTarget(200, 200, mpp),
                                     camera(focal, d), pose, why))
        << "D of size " << d.size() << ": " << why;
    EXPECT_NEAR(pose.position.x, x0, 1e-6);
    EXPECT_NEAR(pose.position.y, y0, 1e-6);
    EXPECT_NEAR(pose.position.z, z, 1e-6);
    // A rotation about z by `angle`: quaternion (0, 0, sin(angle/2), cos(angle/2)), up to sign.
    EXPECT_NEAR(std::abs(pose.orientation.z), std::sin(angle / 2), 1e-6);
    EXPECT_NEAR(std::abs(pose.orientation.w), std::cos(angle / 2), 1e-6);
  }
}

// A rectified image (image_proc's image_rect) is seen through P, undistorted. The camera_info is
// the raw camera's: K and D differ from P. Taken as raw (K and D), the same image gives a pose
// centimetres off: the distortion would be applied twice.
TEST(PlanarPose, RectifiedImageUsesTheProjectionMatrix)
{
  const double rect_focal = 500, mpp = 0.001, x0 = 0.08, y0 = -0.05, z = 0.5, angle = -0.2;
  sensor_msgs::CameraInfo info = cameraInfo(560, {-0.3, 0.1, 0.001, -0.002, 0.0});
  info.P = {rect_focal, 0, 319.5, 0, 0, rect_focal, 239.5, 0, 0, 0, 1, 0};
  const amcr::Affine seen = similarity(rect_focal, mpp, x0, y0, z, angle);
  const amcr_ros::PlanarTarget target = amcr_ros::imageTarget(200, 200, mpp);

  amcr_ros::PnpCamera rectified, raw;
  std::string why;
  ASSERT_TRUE(amcr_ros::pnpCamera(info, true, rectified, why)) << why;
  EXPECT_TRUE(rectified.distortion.empty());
  EXPECT_DOUBLE_EQ(rectified.matrix(0, 0), rect_focal);
  geometry_msgs::Pose pose;
  ASSERT_TRUE(amcr_ros::planarPose(seen, target, rectified, pose, why)) << why;
  EXPECT_NEAR(pose.position.x, x0, 1e-6);
  EXPECT_NEAR(pose.position.y, y0, 1e-6);
  EXPECT_NEAR(pose.position.z, z, 1e-6);

  ASSERT_TRUE(amcr_ros::pnpCamera(info, false, raw, why)) << why;
  EXPECT_EQ(raw.distortion.total(), 5u);
  geometry_msgs::Pose wrong;
  ASSERT_TRUE(amcr_ros::planarPose(seen, target, raw, wrong, why)) << why;
  const double error = std::hypot(wrong.position.x - x0, wrong.position.y - y0, wrong.position.z - z);
  EXPECT_GT(error, 0.02) << "K and D on a rectified image give the same pose: the test shows nothing";
}

TEST(PlanarPose, CameraModelsThatCannotBeUsed)
{
  amcr_ros::PnpCamera c;
  std::string why;
  EXPECT_FALSE(amcr_ros::pnpCamera(cameraInfo(0.0, {}), false, c, why));
  EXPECT_NE(why.find("zeros in K"), std::string::npos) << why;

  sensor_msgs::CameraInfo no_p = cameraInfo(500, {});
  no_p.P = {};
  EXPECT_TRUE(amcr_ros::pnpCamera(no_p, false, c, why)) << why;
  EXPECT_FALSE(amcr_ros::pnpCamera(no_p, true, c, why));
  EXPECT_NE(why.find("zeros in P"), std::string::npos) << why;

  sensor_msgs::CameraInfo fisheye = cameraInfo(500, {0.1, 0.01, 0.0, 0.0});
  fisheye.distortion_model = "equidistant";
  EXPECT_FALSE(amcr_ros::pnpCamera(fisheye, false, c, why));
  EXPECT_NE(why.find("equidistant"), std::string::npos) << why;
  EXPECT_TRUE(amcr_ros::pnpCamera(fisheye, true, c, why)) << why;  // rectified: no distortion to apply

  sensor_msgs::CameraInfo nan = cameraInfo(500, {std::nan(""), 0, 0, 0, 0});
  EXPECT_FALSE(amcr_ros::pnpCamera(nan, false, c, why));
  EXPECT_NE(why.find("non-finite"), std::string::npos) << why;
}

TEST(PlanarPose, RefusesNoMetricSize)
{
  geometry_msgs::Pose pose;
  std::string why;
  const amcr::Affine a = similarity(500, 0.001, 0, 0, 0.5, 0);
  EXPECT_FALSE(amcr_ros::planarPose(a, amcr_ros::imageTarget(200, 200, 0.0), camera(500), pose, why));
  EXPECT_NE(why.find("metric size"), std::string::npos) << why;
}

// The origin of a prototype's target is the centre of its shape's bounding box, in the original
// image's px, wherever the shape lies in its image; the corners surround the shape.
TEST(PlanarPose, TargetOfAPrototypeIsCentredOnItsShape)
{
  cv::Mat image = cv::Mat::zeros(300, 400, CV_8UC1);
  const cv::Rect box(250, 40, 100, 60);  // off-centre: the image's centre is (199.5, 149.5)
  cv::rectangle(image, box, cv::Scalar(255), cv::FILLED);
  const amcr::Prototype prototype("box", image, 128, 20.0);
  const amcr_ros::PlanarTarget target = amcr_ros::planarTarget(prototype, 0.002);
  EXPECT_NEAR(target.origin.x, box.x + 0.5 * (box.width - 1), 1.0);
  EXPECT_NEAR(target.origin.y, box.y + 0.5 * (box.height - 1), 1.0);
  EXPECT_DOUBLE_EQ(target.metres_per_pixel, 0.002);
  EXPECT_LE(target.corners[0].x, box.x);
  EXPECT_LE(target.corners[0].y, box.y);
  EXPECT_GE(target.corners[2].x, box.br().x - 1);
  EXPECT_GE(target.corners[2].y, box.br().y - 1);
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
  const amcr_ros::PlanarTarget target = amcr_ros::imageTarget(size, size, mpp);

  // The truth: the origin (the image's centre, (99.5, 99.5)) at (0, 0, z), the rotation's quaternion about x.
  geometry_msgs::Pose pose;
  std::string why;
  ASSERT_TRUE(amcr_ros::planarPose(h, target, camera(focal), pose, why)) << why;
  EXPECT_NEAR(pose.position.x, 0.0, 1e-6);
  EXPECT_NEAR(pose.position.y, 0.0, 1e-6);
  EXPECT_NEAR(pose.position.z, z, 1e-6);
  EXPECT_NEAR(std::abs(pose.orientation.x), std::sin(tilt / 2), 1e-6);
  EXPECT_NEAR(std::abs(pose.orientation.w), std::cos(tilt / 2), 1e-6);

  // The least-squares affine of the four corners: its pose misses the tilt (by 1.1 degrees).
  std::vector<cv::Point2d> corners(target.corners.begin(), target.corners.end()), mapped;
  for (const auto& c : corners)
    mapped.push_back(amcr::applyHomography(h, c));
  amcr::Affine affine;
  ASSERT_TRUE(amcr::fitAffine(corners, mapped, affine));
  geometry_msgs::Pose affine_pose;
  ASSERT_TRUE(amcr_ros::planarPose(affine, target, camera(focal), affine_pose, why)) << why;
  const double affine_tilt = 2.0 * std::asin(std::min(1.0, std::abs(affine_pose.orientation.x)));
  EXPECT_GT(std::abs(affine_tilt - tilt), 0.5 * M_PI / 180.0) << "the affine's pose is as good: the test shows nothing";
}

TEST(PlanarPose, RefusesACornerBeyondTheHorizon)
{
  geometry_msgs::Pose pose;
  std::string why;
  // w = 1 - 0.01 x is negative at x = 199.
  EXPECT_FALSE(amcr_ros::planarPose(amcr::Homography(1, 0, 0, 0, 1, 0, -0.01, 0, 1),
                                    amcr_ros::imageTarget(200, 200, 0.001), camera(500), pose, why));
  EXPECT_NE(why.find("horizon"), std::string::npos) << why;
}
}  // namespace
