#include "message_conversion.h"

#include <geometry_msgs/Point32.h>

namespace amcr_ros
{
namespace
{
void toArray(const amcr::Affine& a, boost::array<double, 6>& out)
{
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
      out[static_cast<std::size_t>(r * 3 + c)] = a(r, c);
}
void toArray(const amcr::Homography& h, boost::array<double, 9>& out)
{
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[static_cast<std::size_t>(r * 3 + c)] = h(r, c);
}
std::uint8_t toMsg(amcr::ObjectState state)
{
  switch (state)
  {
    case amcr::ObjectState::kTentative:
      return amcr::Recognition::TENTATIVE;
    case amcr::ObjectState::kConfirmed:
      return amcr::Recognition::CONFIRMED;
    case amcr::ObjectState::kHeld:
      return amcr::Recognition::HELD;
    case amcr::ObjectState::kLost:
      return amcr::Recognition::LOST;
  }
  return amcr::Recognition::TENTATIVE;
}
}  // namespace

amcr::Recognition toMsg(const amcr::RecognizedObject& object)
{
  amcr::Recognition msg;
  msg.label = object.label;
  msg.instance = object.instance;
  msg.prototype_id = object.prototype_id;
  msg.track_id = object.track_id;
  msg.state = toMsg(object.state);
  msg.score = object.score;
  msg.visible_share = object.visible_share;
  msg.support = object.support;
  toArray(object.image_to_prototype, msg.image_to_prototype);
  toArray(object.prototype_to_image, msg.prototype_to_image);
  toArray(object.homography, msg.homography);
  msg.homography_valid = object.homography_valid;
  msg.anisotropy = object.anisotropy;
  msg.viewing_angle_deg = object.viewing_angle_deg;
  msg.outline.points.reserve(object.outline.size());
  for (const cv::Point2d& p : object.outline)
  {
    geometry_msgs::Point32 q;
    q.x = static_cast<float>(p.x);
    q.y = static_cast<float>(p.y);
    q.z = 0.f;
    msg.outline.points.push_back(q);
  }
  msg.correspondences.reserve(object.correspondences.size());
  for (const amcr::Correspondence& c : object.correspondences)
  {
    amcr::PointCorrespondence m;
    m.image_x = c.image.x;
    m.image_y = c.image.y;
    m.prototype_x = c.prototype.x;
    m.prototype_y = c.prototype.y;
    msg.correspondences.push_back(m);
  }
  msg.pose_valid = false;
  msg.pose.orientation.w = 1.0;
  return msg;
}

std::string stateName(std::uint8_t state)
{
  for (amcr::ObjectState s : {amcr::ObjectState::kTentative, amcr::ObjectState::kConfirmed, amcr::ObjectState::kHeld,
                              amcr::ObjectState::kLost})
    if (toMsg(s) == state)
      return amcr::toString(s);
  return "unknown";
}

amcr::Recognitions toMsg(const amcr::RecognitionResult& result, const std_msgs::Header& header)
{
  amcr::Recognitions msg;
  msg.header = header;
  msg.iteration = result.iteration;
  msg.iterations = result.iterations;
  msg.processing_ms = result.time_ms;
  for (const amcr::RecognizedObject& o : result.objects)  // the core's order: best score first
    msg.objects.push_back(toMsg(o));
  for (const amcr::RecognizedObject& o : result.lost)
    msg.lost.push_back(toMsg(o));
  return msg;
}

amcr::PrototypeTable toMsg(const amcr::PrototypeMemory* memory, const std::string& directory, std::uint32_t version,
                           const ros::Time& stamp)
{
  amcr::PrototypeTable msg;
  msg.header.stamp = stamp;
  msg.version = version;
  msg.directory = directory;
  if (memory == nullptr)
    return msg;
  msg.labels = memory->labels();
  for (std::size_t i = 0; i < memory->size(); ++i)
  {
    amcr::PrototypeInfo info;
    info.label = (*memory)[i].label();
    info.instance = (*memory)[i].instance();
    info.prototype_id = static_cast<int>(i);
    info.width = (*memory)[i].originalSize().width;
    info.height = (*memory)[i].originalSize().height;
    msg.prototypes.push_back(info);
  }
  return msg;
}
}  // namespace amcr_ros
