// objectMarkers (src/ros/object_markers.cpp): the outline and label of a posed object, the deletes
// for an object without a pose, a lost track and a restart, and odd input.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "object_markers.h"

namespace
{
using visualization_msgs::Marker;
using Outlines = std::vector<std::vector<geometry_msgs::Point>>;

geometry_msgs::Point point(double x, double y)
{
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  return p;
}

// A 0.2 m x 0.1 m rectangle about the plane frame's origin, not closed.
std::vector<geometry_msgs::Point> rectangle()
{
  return {point(-0.1, -0.05), point(0.1, -0.05), point(0.1, 0.05), point(-0.1, 0.05)};
}

amcr::Recognition object(const std::string& label, int track_id, bool pose_valid)
{
  amcr::Recognition o;
  o.label = label;
  o.track_id = track_id;
  o.state = amcr::Recognition::CONFIRMED;
  o.pose_valid = pose_valid;
  o.pose.orientation.w = 1;
  if (pose_valid)
  {
    o.pose.position.x = 0.1;
    o.pose.position.y = -0.2;
    o.pose.position.z = 0.8;
    // 90 degrees about the camera's z axis.
    o.pose.orientation.z = std::sqrt(0.5);
    o.pose.orientation.w = std::sqrt(0.5);
  }
  return o;
}

amcr::Recognitions recognitions()
{
  amcr::Recognitions r;
  r.header.frame_id = "camera";
  r.header.stamp = ros::Time(12, 345);
  return r;
}

void expectDeletes(const amcr::Recognitions& r, const Marker& outline, const Marker& label, int id)
{
  EXPECT_EQ(outline.action, Marker::DELETE);
  EXPECT_EQ(outline.ns, "outline");
  EXPECT_EQ(outline.id, id);
  EXPECT_EQ(outline.header.frame_id, r.header.frame_id);
  EXPECT_EQ(label.action, Marker::DELETE);
  EXPECT_EQ(label.ns, "label");
  EXPECT_EQ(label.id, id);
  EXPECT_EQ(label.header.frame_id, r.header.frame_id);
}

TEST(ObjectMarkers, PosedObjectGivesClosedOutlineAndLabel)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("bird", 7, true));
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {rectangle()}, false);
  ASSERT_EQ(array.markers.size(), 2u);

  int lines = 0, texts = 0;
  for (const Marker& m : array.markers)
  {
    EXPECT_EQ(m.action, Marker::ADD);
    EXPECT_EQ(m.id, 7);
    EXPECT_EQ(m.header.frame_id, "camera");
    EXPECT_EQ(m.header.stamp, ros::Time(12, 345));
    EXPECT_EQ(m.lifetime, ros::Duration(0));
    EXPECT_FALSE(m.frame_locked);
    if (m.type == Marker::LINE_STRIP)
    {
      ++lines;
      EXPECT_EQ(m.ns, "outline");
      EXPECT_EQ(m.pose, r.objects[0].pose);
      const std::vector<geometry_msgs::Point> outline = rectangle();
      ASSERT_EQ(m.points.size(), outline.size() + 1);
      for (std::size_t i = 0; i < outline.size(); ++i)
        EXPECT_EQ(m.points[i], outline[i]);
      EXPECT_EQ(m.points.front(), m.points.back());
      EXPECT_NEAR(m.scale.x, 0.015 * 0.2, 1e-12);
      EXPECT_FLOAT_EQ(m.color.a, 1.f);
    }
    else if (m.type == Marker::TEXT_VIEW_FACING)
    {
      ++texts;
      EXPECT_EQ(m.ns, "label");
      EXPECT_EQ(m.text, "bird #7");
      EXPECT_NEAR(m.scale.z, 0.2 * 0.2, 1e-12);
      // Plane frame (0, -0.05 - 0.04, -0.04), turned 90 degrees about z: (0.09, 0, -0.04) from the origin.
      EXPECT_NEAR(m.pose.position.x, 0.1 + 0.09, 1e-9);
      EXPECT_NEAR(m.pose.position.y, -0.2, 1e-9);
      EXPECT_NEAR(m.pose.position.z, 0.8 - 0.04, 1e-9);
      EXPECT_FLOAT_EQ(m.color.r, 1.f);
      EXPECT_FLOAT_EQ(m.color.g, 1.f);
      EXPECT_FLOAT_EQ(m.color.b, 1.f);
      EXPECT_FLOAT_EQ(m.color.a, 1.f);
    }
  }
  EXPECT_EQ(lines, 1);
  EXPECT_EQ(texts, 1);
}

TEST(ObjectMarkers, ClosedOutlineIsNotClosedTwiceAndTentativeIsSaid)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("star", 3, true));
  r.objects[0].state = amcr::Recognition::TENTATIVE;
  std::vector<geometry_msgs::Point> outline = rectangle();
  outline.push_back(outline.front());
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {outline}, false);
  ASSERT_EQ(array.markers.size(), 2u);
  EXPECT_EQ(array.markers[0].points.size(), outline.size());
  EXPECT_EQ(array.markers[1].text, "star #3 (tentative)");
}

TEST(ObjectMarkers, TinyOutlineKeepsMinimumSizes)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("dot", 1, true));
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {{point(0, 0), point(0.001, 0)}}, false);
  ASSERT_EQ(array.markers.size(), 2u);
  EXPECT_DOUBLE_EQ(array.markers[0].scale.x, 0.001);
  EXPECT_DOUBLE_EQ(array.markers[1].scale.z, 0.01);
}

TEST(ObjectMarkers, ObjectWithoutPoseGivesDeletes)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("bird", 4, false));
  r.objects.push_back(object("bone", 5, true));  // posed, but its outline is empty
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {{}, {}}, false);
  ASSERT_EQ(array.markers.size(), 4u);
  expectDeletes(r, array.markers[0], array.markers[1], 4);
  expectDeletes(r, array.markers[2], array.markers[3], 5);
}

TEST(ObjectMarkers, LostObjectGivesDeletes)
{
  amcr::Recognitions r = recognitions();
  r.lost.push_back(object("bird", 9, true));
  r.lost[0].state = amcr::Recognition::LOST;
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {}, false);
  ASSERT_EQ(array.markers.size(), 2u);
  expectDeletes(r, array.markers[0], array.markers[1], 9);
}

TEST(ObjectMarkers, RestartGivesDeleteAllFirst)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("bird", 1, true));
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {rectangle()}, true);
  ASSERT_EQ(array.markers.size(), 3u);
  EXPECT_EQ(array.markers[0].action, Marker::DELETEALL);
  EXPECT_EQ(array.markers[1].action, Marker::ADD);
  EXPECT_EQ(array.markers[2].action, Marker::ADD);

  const visualization_msgs::MarkerArray empty = amcr_ros::objectMarkers(recognitions(), {}, true);
  ASSERT_EQ(empty.markers.size(), 1u);
  EXPECT_EQ(empty.markers[0].action, Marker::DELETEALL);
}

TEST(ObjectMarkers, MismatchedOutlineSizesDoNotThrow)
{
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("bird", 1, true));
  r.objects.push_back(object("bone", 2, true));
  visualization_msgs::MarkerArray array;
  // Fewer outlines than objects: the second object counts as without a pose.
  ASSERT_NO_THROW(array = amcr_ros::objectMarkers(r, {rectangle()}, false));
  ASSERT_EQ(array.markers.size(), 4u);
  EXPECT_EQ(array.markers[0].action, Marker::ADD);
  expectDeletes(r, array.markers[2], array.markers[3], 2);
  // More outlines than objects: the extra ones are ignored.
  ASSERT_NO_THROW(array = amcr_ros::objectMarkers(r, {rectangle(), rectangle(), rectangle()}, false));
  EXPECT_EQ(array.markers.size(), 4u);
  // No objects, outlines anyway.
  ASSERT_NO_THROW(array = amcr_ros::objectMarkers(recognitions(), {rectangle()}, false));
  EXPECT_TRUE(array.markers.empty());
  // Non-finite points and a zero quaternion.
  r.objects[0].pose.orientation = geometry_msgs::Quaternion();
  ASSERT_NO_THROW(array = amcr_ros::objectMarkers(r, {{point(NAN, 0), point(INFINITY, 1)}, {point(0, 0)}}, false));
  EXPECT_EQ(array.markers.size(), 4u);
}

TEST(ObjectMarkers, ColoursDifferBetweenTracksAndRepeat)
{
  for (int id = 1; id < 20; ++id)
  {
    const std_msgs::ColorRGBA a = amcr_ros::trackColor(id), b = amcr_ros::trackColor(id + 1);
    EXPECT_GT(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b), 0.1f) << "ids " << id;
    EXPECT_EQ(a, amcr_ros::trackColor(id));
    EXPECT_FLOAT_EQ(a.a, 1.f);
    for (float c : {a.r, a.g, a.b})
    {
      EXPECT_GE(c, 0.f);
      EXPECT_LE(c, 1.f);
    }
  }
  amcr::Recognitions r = recognitions();
  r.objects.push_back(object("bird", 1, true));
  r.objects.push_back(object("bird", 2, true));
  const visualization_msgs::MarkerArray array = amcr_ros::objectMarkers(r, {rectangle(), rectangle()}, false);
  ASSERT_EQ(array.markers.size(), 4u);
  EXPECT_NE(array.markers[0].color, array.markers[2].color);
}
}  // namespace
