// objectMarkers and trackColor (object_markers.h): the markers of one amcr/Recognitions message.
#include "object_markers.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>
#include <tf2/LinearMath/Quaternion.h>

namespace amcr_ros
{
namespace
{
constexpr double kLineWidthShare = 0.015;  // of the outline's larger side
constexpr double kMinLineWidth = 0.001;    // m
constexpr double kTextHeightShare = 0.2;   // of the outline's larger side
constexpr double kMinTextHeight = 0.01;    // m

struct Box
{
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

/// The bounding box of the finite points (all zero when there are none).
Box boundingBox(const std::vector<geometry_msgs::Point>& points)
{
  Box box;
  bool any = false;
  for (const geometry_msgs::Point& p : points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      continue;
    if (!any)
    {
      box.min_x = box.max_x = p.x;
      box.min_y = box.max_y = p.y;
      any = true;
      continue;
    }
    box.min_x = std::min(box.min_x, p.x);
    box.max_x = std::max(box.max_x, p.x);
    box.min_y = std::min(box.min_y, p.y);
    box.max_y = std::max(box.max_y, p.y);
  }
  return box;
}

/// v rotated by q (normalised here; the identity when q is zero or not finite).
geometry_msgs::Point rotate(const geometry_msgs::Quaternion& q, const geometry_msgs::Point& v)
{
  const tf2::Quaternion rotation(q.x, q.y, q.z, q.w);
  const double norm = rotation.length();
  if (!(norm > 0) || !std::isfinite(norm))
    return v;
  const tf2::Vector3 r = tf2::quatRotate(rotation / norm, tf2::Vector3(v.x, v.y, v.z));
  geometry_msgs::Point out;
  out.x = r.x();
  out.y = r.y();
  out.z = r.z();
  return out;
}

bool samePoint(const geometry_msgs::Point& a, const geometry_msgs::Point& b)
{
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

visualization_msgs::Marker baseMarker(const std_msgs::Header& header, const std::string& ns, std::int32_t id)
{
  visualization_msgs::Marker marker;
  marker.header = header;
  marker.ns = ns;
  marker.id = id;
  marker.pose.orientation.w = 1;
  marker.lifetime = ros::Duration(0);
  marker.frame_locked = false;
  return marker;
}

void appendDeletes(const std_msgs::Header& header, std::int32_t id, visualization_msgs::MarkerArray& out)
{
  for (const char* ns : {"outline", "label"})
  {
    visualization_msgs::Marker marker = baseMarker(header, ns, id);
    marker.action = visualization_msgs::Marker::DELETE;
    out.markers.push_back(marker);
  }
}

void appendMarkers(const std_msgs::Header& header, const amcr::Recognition& object,
                   const std::vector<geometry_msgs::Point>& outline, visualization_msgs::MarkerArray& out)
{
  const Box box = boundingBox(outline);
  double side = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  if (!std::isfinite(side))
    side = 0;

  visualization_msgs::Marker line = baseMarker(header, "outline", object.track_id);
  line.type = visualization_msgs::Marker::LINE_STRIP;
  line.action = visualization_msgs::Marker::ADD;
  line.pose = object.pose;
  line.points = outline;
  if (!samePoint(line.points.front(), line.points.back()))
    line.points.push_back(line.points.front());
  line.scale.x = std::max(kLineWidthShare * side, kMinLineWidth);
  line.color = trackColor(object.track_id);
  out.markers.push_back(line);

  const double height = std::max(kTextHeightShare * side, kMinTextHeight);
  visualization_msgs::Marker text = baseMarker(header, "label", object.track_id);
  text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
  text.action = visualization_msgs::Marker::ADD;
  geometry_msgs::Point anchor;  // in the plane frame: above the outline, towards the camera
  anchor.x = (box.min_x + box.max_x) / 2;
  anchor.y = box.min_y - height;
  anchor.z = -height;
  const geometry_msgs::Point offset = rotate(object.pose.orientation, anchor);
  text.pose.position.x = object.pose.position.x + offset.x;
  text.pose.position.y = object.pose.position.y + offset.y;
  text.pose.position.z = object.pose.position.z + offset.z;
  text.scale.z = height;
  text.color.r = text.color.g = text.color.b = text.color.a = 1;
  text.text = object.label + " #" + std::to_string(object.track_id);
  if (object.state == amcr::Recognition::TENTATIVE)
    text.text += " (tentative)";
  out.markers.push_back(text);
}
}  // namespace

std_msgs::ColorRGBA trackColor(std::int32_t track_id)
{
  constexpr double kGoldenConjugate = 0.6180339887498949;
  double hue = std::fmod(static_cast<double>(track_id) * kGoldenConjugate, 1.0);
  if (hue < 0)
    hue += 1;
  // Saturation 0.85, value 1; OpenCV's float HSV takes the hue in degrees.
  const cv::Mat3f hsv(1, 1, cv::Vec3f(static_cast<float>(360.0 * hue), 0.85f, 1.0f));
  cv::Mat3f rgb;
  cv::cvtColor(hsv, rgb, cv::COLOR_HSV2RGB);
  std_msgs::ColorRGBA color;
  color.r = rgb(0, 0)[0];
  color.g = rgb(0, 0)[1];
  color.b = rgb(0, 0)[2];
  color.a = 1.f;
  return color;
}

visualization_msgs::MarkerArray objectMarkers(const amcr::Recognitions& recognitions,
                                              const std::vector<std::vector<geometry_msgs::Point>>& outlines,
                                              bool restarted)
{
  const std_msgs::Header& header = recognitions.header;
  visualization_msgs::MarkerArray out;
  if (restarted)
  {
    visualization_msgs::Marker marker = baseMarker(header, "", 0);
    marker.action = visualization_msgs::Marker::DELETEALL;
    out.markers.push_back(marker);
  }
  for (std::size_t i = 0; i < recognitions.objects.size(); ++i)
  {
    const amcr::Recognition& object = recognitions.objects[i];
    if (object.pose_valid && i < outlines.size() && !outlines[i].empty())
      appendMarkers(header, object, outlines[i], out);
    else
      appendDeletes(header, object.track_id, out);
  }
  for (const amcr::Recognition& object : recognitions.lost)
    appendDeletes(header, object.track_id, out);
  return out;
}
}  // namespace amcr_ros
