// toMsg of one recognized object (src/ros/message_conversion.cpp): every
// field of amcr/Recognition as the core has it, the homography row-major and
// the view (anisotropy and viewing angle).
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "message_conversion.h"

namespace
{
TEST(MessageConversion, ObjectFieldsWithHomographyAndView)
{
  amcr::RecognizedObject object;
  object.label = "target";
  object.instance = "target/target-2.png";
  object.prototype_id = 1;
  object.track_id = 5;
  object.state = amcr::ObjectState::kHeld;
  object.score = 0.91;
  object.visible_share = 0.63;
  object.support = 7;
  object.image_to_prototype = amcr::Affine(0.5, 0.1, -3, -0.1, 0.5, 4);
  object.prototype_to_image = amcr::Affine(1.9, -0.4, 30, 0.4, 1.9, -8);
  object.homography = amcr::Homography(1.9, -0.4, 30, 0.4, 1.9, -8, 0.0002, -0.0001, 1);
  object.homography_valid = true;
  object.anisotropy = 2.5;
  object.viewing_angle_deg = 66.42;
  object.outline = {{10, 20}, {30, 40}};
  object.correspondences.push_back({cv::Point2d(11, 12), cv::Point2d(13, 14)});

  const amcr::Recognition msg = amcr_ros::toMsg(object);
  EXPECT_EQ(msg.label, "target");
  EXPECT_EQ(msg.instance, "target/target-2.png");
  EXPECT_EQ(msg.prototype_id, 1);
  EXPECT_EQ(msg.track_id, 5);
  EXPECT_EQ(msg.state, amcr::Recognition::HELD);
  EXPECT_DOUBLE_EQ(msg.score, 0.91);
  EXPECT_DOUBLE_EQ(msg.visible_share, 0.63);
  EXPECT_EQ(msg.support, 7);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
    {
      EXPECT_DOUBLE_EQ(msg.image_to_prototype[r * 3 + c], object.image_to_prototype(r, c));
      EXPECT_DOUBLE_EQ(msg.prototype_to_image[r * 3 + c], object.prototype_to_image(r, c));
    }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_DOUBLE_EQ(msg.homography[r * 3 + c], object.homography(r, c)) << "row " << r << " column " << c;
  EXPECT_TRUE(msg.homography_valid);
  EXPECT_DOUBLE_EQ(msg.anisotropy, 2.5);
  EXPECT_DOUBLE_EQ(msg.viewing_angle_deg, 66.42);
  ASSERT_EQ(msg.outline.points.size(), 2u);
  EXPECT_FLOAT_EQ(msg.outline.points[1].y, 40.f);
  ASSERT_EQ(msg.correspondences.size(), 1u);
  EXPECT_DOUBLE_EQ(msg.correspondences[0].prototype_y, 14.0);
  EXPECT_FALSE(msg.pose_valid);
  EXPECT_DOUBLE_EQ(msg.pose.orientation.w, 1.0);

  // Not used: the flag says so, and the homography is whatever the core put there (the affine's lift).
  object.homography_valid = false;
  object.homography = amcr::liftAffine(object.prototype_to_image);
  const amcr::Recognition plain = amcr_ros::toMsg(object);
  EXPECT_FALSE(plain.homography_valid);
  EXPECT_DOUBLE_EQ(plain.homography[6], 0.0);
  EXPECT_DOUBLE_EQ(plain.homography[7], 0.0);
  EXPECT_DOUBLE_EQ(plain.homography[8], 1.0);
}
// Every state has its constant; the objects whose tracks ended go to `lost`.
TEST(MessageConversion, StatesAndLostObjects)
{
  amcr::RecognizedObject object;
  object.state = amcr::ObjectState::kTentative;
  EXPECT_EQ(amcr_ros::toMsg(object).state, amcr::Recognition::TENTATIVE);
  object.state = amcr::ObjectState::kConfirmed;
  EXPECT_EQ(amcr_ros::toMsg(object).state, amcr::Recognition::CONFIRMED);

  amcr::RecognitionResult result;
  result.objects.push_back(object);
  object.track_id = 9;
  object.state = amcr::ObjectState::kLost;
  result.lost.push_back(object);
  const amcr::Recognitions msg = amcr_ros::toMsg(result, std_msgs::Header());
  ASSERT_EQ(msg.objects.size(), 1u);
  ASSERT_EQ(msg.lost.size(), 1u);
  EXPECT_EQ(msg.lost[0].track_id, 9);
  EXPECT_EQ(msg.lost[0].state, amcr::Recognition::LOST);
  EXPECT_EQ(amcr_ros::stateName(amcr::Recognition::HELD), "held");
  EXPECT_EQ(amcr_ros::stateName(amcr::Recognition::LOST), "lost");
  EXPECT_EQ(amcr_ros::stateName(200), "unknown");
}

// The label table: the distinct labels, and a row per instance (a label may have several).
TEST(MessageConversion, LabelTableListsLabelsWithTheirInstances)
{
  amcr::Params params;
  params.prototype_size = 32;
  cv::Mat disc = cv::Mat::zeros(60, 80, CV_8UC1), box = cv::Mat::zeros(60, 80, CV_8UC1);
  cv::circle(disc, cv::Point(40, 30), 20, cv::Scalar(255), -1);
  cv::rectangle(box, cv::Rect(20, 15, 40, 30), cv::Scalar(255), -1);
  amcr::PrototypeMemory memory;
  memory.add("disc", disc, params, "disc/small.png");
  memory.add("disc", box, params, "disc/square.png");
  memory.add("box", box, params);
  const amcr::PrototypeTable table = amcr_ros::toMsg(&memory, "/prototypes", 7u, ros::Time(5));
  EXPECT_EQ(table.labels, (std::vector<std::string>{"disc", "box"}));
  ASSERT_EQ(table.prototypes.size(), 3u);
  EXPECT_EQ(table.prototypes[0].label, "disc");
  EXPECT_EQ(table.prototypes[0].instance, "disc/small.png");
  EXPECT_EQ(table.prototypes[1].label, "disc");
  EXPECT_EQ(table.prototypes[1].instance, "disc/square.png");
  EXPECT_EQ(table.prototypes[1].prototype_id, 1);
  EXPECT_EQ(table.prototypes[2].instance, "box");
  EXPECT_EQ(table.prototypes[2].width, 80);
  EXPECT_EQ(table.directory, "/prototypes");
  EXPECT_EQ(table.version, 7u);
}
}  // namespace
