// The generic rostest tester (recognizer_tester.cpp): with camera_info and a metric size, the pose,
// the tf frame and the RViz markers of the recognized object.
#include <string>

#include <visualization_msgs/MarkerArray.h>

#include "recognizer_test.h"

namespace recognizer_tester
{
// With camera_info and a metric size: the pose and the tf frame match the
// truth. A camera_info with zeros in K is refused first.
TEST_F(RecognizerTest, PoseAndFrameWithCameraInfo)
{
  if (!check_pose_)
    return;  // this configuration checks that no pose comes without camera_info (RecognizesTheShownPrototype)
  ASSERT_TRUE(similarity_) << "~check_pose needs scale_x = scale_y and shear = 0";
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(waitUntil([] { return info_pub_.getNumSubscribers() > 0; }, timeout_))
      << "nobody subscribes to " << info_topic_;
  info_pub_.publish(cameraInfo(0.0));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "zeros in K")) << "no error about a camera_info with zeros in K";
  info_pub_.publish(cameraInfo(focal_));

  // The truth: the centre of the shape's bounding box is the frame's origin; the plane is parallel
  // to the image, seen through the focal of the frames (P's when rectified).
  const double z = focal_ * metres_per_pixel_ / scale_;
  const double cx = 0.5 * (scene_.size.width - 1), cy = 0.5 * (scene_.size.height - 1);
  const cv::Point2d origin = amcr::applyAffine(truth_, poseOrigin());
  const tf2::Vector3 expected((origin.x - cx) * z / focal_, (origin.y - cy) * z / focal_, z);

  // The pose is checked once the object has been recognized with a pose in
  // kSettleFrames frames in a row: the first report of a shape with long arcs
  // (the crescent) can still slide along them, and the tracked fit settles.
  constexpr int kSettleFrames = 5;
  amcr::RecognitionsConstPtr last;
  int frames = 0, in_a_row = 0;
  for (; frames < max_frames_; ++frames)
  {
    last = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
    ASSERT_TRUE(last);
    in_a_row = (recognizedRight(*last) && last->objects[0].pose_valid) ? in_a_row + 1 : 0;
    if (in_a_row >= kSettleFrames)
      break;
  }
  ASSERT_LT(frames, max_frames_) << "no settled pose for " << label_ << " within " << max_frames_ << " frames";
  const amcr::Recognition& object = last->objects[0];
  const tf2::Vector3 position(object.pose.position.x, object.pose.position.y, object.pose.position.z);
  EXPECT_LT((position - expected).length(), translation_tolerance_)
      << "pose (" << position.x() << ", " << position.y() << ", " << position.z() << ") m, truth (" << expected.x()
      << ", " << expected.y() << ", " << expected.z() << ") m";

  const std::string child = frame_prefix_ + object.label + "_" + std::to_string(object.track_id);
  geometry_msgs::TransformStamped t;
  try
  {
    t = tf_buffer_->lookupTransform("camera", child, last->header.stamp, ros::Duration(timeout_));
  }
  catch (const tf2::TransformException& e)
  {
    FAIL() << "no tf frame " << child << ": " << e.what();
  }
  const tf2::Vector3 tf_position(t.transform.translation.x, t.transform.translation.y, t.transform.translation.z);
  EXPECT_LT((tf_position - expected).length(), translation_tolerance_);
  ROS_INFO("pose of %s: (%.4f, %.4f, %.4f) m, truth (%.4f, %.4f, %.4f) m", child.c_str(), position.x(), position.y(),
           position.z(), expected.x(), expected.y(), expected.z());
}

// ~markers: while the object is recognized with a pose, its outline (a line
// strip in the camera frame, posed like the object) and its label; once it
// leaves the image and its track is lost, both are deleted.
TEST_F(RecognizerTest, MarkersFollowTheObjectAndAreDeletedWhenItLeaves)
{
  if (!check_markers_)
    return;  // configurations without a pose have no markers to show
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  info_pub_.publish(cameraInfo(focal_));
  Inbox<visualization_msgs::MarkerArray> markers;
  markers.subscribe(*nh_, node_ + "/markers", 100);
  ASSERT_TRUE(waitUntil([&] { return markers.publishers() > 0; }, timeout_)) << "nobody publishes " << node_
                                                                             << "/markers";
  // The nodelet draws markers only while someone listens: it learns of us within a few frames.
  int track = -1;
  visualization_msgs::MarkerArrayConstPtr shown;
  for (int frames = 0; frames < max_frames_ && !shown; ++frames)
  {
    auto r = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
    ASSERT_TRUE(r);
    if (!recognizedRight(*r) || !r->objects[0].pose_valid)
      continue;
    track = r->objects[0].track_id;
    const ros::Time stamp = r->header.stamp;
    shown = markers.waitFor(
        [&](const visualization_msgs::MarkerArray& a) {
          for (const auto& m : a.markers)
            if (m.header.stamp == stamp && m.ns == "outline" && m.id == track &&
                m.action == visualization_msgs::Marker::ADD)
              return true;
          return false;
        },
        0.5);
  }
  ASSERT_TRUE(shown) << "no outline marker for the recognized " << label_;
  bool outline = false, text = false;
  for (const auto& m : shown->markers)
  {
    if (m.id != track)
      continue;
    if (m.ns == "outline")
    {
      outline = true;
      EXPECT_EQ(m.type, visualization_msgs::Marker::LINE_STRIP);
      EXPECT_EQ(m.header.frame_id, "camera");
      EXPECT_GT(m.points.size(), 10u);
      EXPECT_GT(m.pose.position.z, 0.0) << "the outline is not placed at the object's pose";
    }
    if (m.ns == "label")
    {
      text = true;
      EXPECT_EQ(m.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
      EXPECT_NE(m.text.find(label_), std::string::npos) << m.text;
      EXPECT_NE(m.text.find("#" + std::to_string(track)), std::string::npos) << m.text;
    }
  }
  EXPECT_TRUE(outline && text) << "outline " << outline << ", label " << text;

  // The object leaves: frames of the background alone until its track is lost.
  const cv::Mat background = amcr_test::renderBackground(scene_);
  visualization_msgs::MarkerArrayConstPtr deleted;
  for (int frames = 0; frames < 60 && !deleted; ++frames)
  {
    const ros::Time stamp = nextStamp();
    ASSERT_TRUE(publishAndWait(
        frame(amcr_test::addNoise(background, scene_.clutter.noise_sigma, 777 + frames), enc::MONO8, stamp)));
    deleted = markers.waitFor(
        [&](const visualization_msgs::MarkerArray& a) {
          int deletes = 0;
          for (const auto& m : a.markers)
            deletes += m.header.stamp == stamp && m.id == track && m.action == visualization_msgs::Marker::DELETE;
          return deletes == 2;
        },
        0.5);
  }
  EXPECT_TRUE(deleted) << "the markers of track " << track << " were not deleted after the object left";
  markers.shutdown();
}
}  // namespace recognizer_tester
