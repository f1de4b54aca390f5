// The generic rostest tester (recognizer_tester.cpp): the memory loaded at runtime through
// ~load_prototypes, and the shown prototype recognized with the true affine.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "recognizer_test.h"

namespace recognizer_tester
{
// The nodelet was started with a missing prototype directory: it stays up,
// refuses a bad directory with an error text, and takes a good one.
TEST_F(RecognizerTest, StartsWithoutPrototypesAndLoadsThemAtRuntime)
{
  ASSERT_TRUE(ros::service::waitForService(node_ + "/load_prototypes", ros::Duration(timeout_)));
  // Before any memory: the latched table is empty.
  auto empty = prototypes_.waitFor([](const amcr::PrototypeTable& t) { return t.prototypes.empty(); }, timeout_);
  EXPECT_TRUE(empty) << "no empty label table on " << node_ << "/prototypes";
  if (empty)
  {
    EXPECT_EQ(empty->version, 0u) << "a table version before any memory";
  }

  amcr::LoadPrototypes bad;
  bad.request.directory = dir_->file("no_such_directory");
  ASSERT_TRUE(ros::service::call(node_ + "/load_prototypes", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_NE(bad.response.message.find("no_such_directory"), std::string::npos) << bad.response.message;

  ensurePrototypes();
  auto table = prototypes_.waitFor([](const amcr::PrototypeTable& t) { return t.prototypes.size() == 3; }, timeout_);
  ASSERT_TRUE(table) << "no label table with 3 prototypes on " << node_ << "/prototypes";
  std::vector<std::string> labels;
  for (const auto& p : table->prototypes)
  {
    labels.push_back(p.label);
    EXPECT_EQ(p.width, amcr_test::kPrototypeImageSize);
    EXPECT_EQ(p.height, amcr_test::kPrototypeImageSize);
  }
  EXPECT_NE(std::find(labels.begin(), labels.end(), label_), labels.end());
  EXPECT_EQ(table->directory, dir_->path());
  EXPECT_EQ(table->version, 1u) << "the refused load must not count";
}

// The expected label with the true affine within a bounded number of frames.
TEST_F(RecognizerTest, RecognizesTheShownPrototype)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription()) << "nobody subscribes to " << image_topic_;
  int frames = 0;
  amcr::RecognitionsConstPtr last;
  for (; frames < max_frames_; ++frames)
  {
    last = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
    ASSERT_TRUE(last) << "no recognitions for frame " << frames << " within " << timeout_ << " s";
    EXPECT_EQ(last->header.frame_id, "camera");
    if (recognizedRight(*last))
      break;
  }
  ASSERT_LT(frames, max_frames_) << label_ << " not recognized within " << max_frames_ << " frames";
  EXPECT_EQ(last->prototype_table_version, 1u) << "the recognitions do not carry the label table's version";
  const amcr::Recognition& object = last->objects[0];
  EXPECT_GE(object.score, 0.0);
  EXPECT_LE(object.score, 1.0);
  EXPECT_GE(object.support, 1);
  EXPECT_GE(object.track_id, 1);
  EXPECT_FALSE(object.outline.points.empty());
  EXPECT_FALSE(object.correspondences.empty());
  // The view: anisotropy >= 1 and its viewing angle; the homography is the affine's lift when not used.
  EXPECT_GE(object.anisotropy, 1.0);
  EXPECT_NEAR(object.viewing_angle_deg, std::acos(1.0 / object.anisotropy) * 180.0 / M_PI, 1e-9);
  EXPECT_EQ(object.homography[8], 1.0);
  if (!object.homography_valid)
  {
    for (std::size_t i = 0; i < 6; ++i)
      EXPECT_DOUBLE_EQ(object.homography[i], object.prototype_to_image[i]) << "homography entry " << i;
  }
  if (!check_pose_)
  {
    EXPECT_FALSE(object.pose_valid) << "a pose without camera_info";
  }
  RecordProperty("frames_to_recognition", frames + 1);
  ROS_INFO("%s recognized after %d frames, corner error %.2f px", label_.c_str(), frames + 1, cornerError(object));
}
}  // namespace recognizer_tester
