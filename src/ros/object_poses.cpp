#include "object_poses.h"

#include <image_transport/camera_common.h>
#include <ros/names.h>
#include <xmlrpcpp/XmlRpcException.h>

namespace amcr_ros
{
namespace
{
/// The last name of a topic ("/camera/image_rect_color" -> "image_rect_color").
std::string baseName(const std::string& topic)
{
  const std::size_t slash = topic.rfind('/');
  return slash == std::string::npos ? topic : topic.substr(slash + 1);
}
}  // namespace

ObjectPoses::ObjectPoses(ros::NodeHandle nh, const ros::NodeHandle& private_nh, const std::string& image_topic)
{
  loadParameters(private_nh, image_topic);
  // An explicit remap of camera_info wins; otherwise the image's sibling (image_transport's rule).
  const std::string remapped = nh.resolveName("camera_info", true);
  camera_info_topic_ = remapped != nh.resolveName("camera_info", false)
                           ? remapped
                           : image_transport::getCameraInfoTopic(image_topic);
  sub_info_ = nh.subscribe(camera_info_topic_, 1, &ObjectPoses::cameraInfoCb, this);
  ROS_INFO("camera_info from %s; poses for %s images of %s", camera_info_topic_.c_str(),
           rectified_ ? "rectified" : "raw", image_topic.c_str());
}

void ObjectPoses::loadParameters(const ros::NodeHandle& private_nh, const std::string& image_topic)
{
  // The node's own name keeps two recognizers' frames apart: /left/amcr -> left/amcr/.
  std::string node = private_nh.getNamespace();
  while (!node.empty() && node.front() == '/')
    node.erase(0, 1);
  private_nh.param<std::string>("frame_prefix", frame_prefix_, node.empty() ? "amcr/" : node + "/");
  if (!private_nh.getParam("rectified", rectified_))
    rectified_ = baseName(image_topic).rfind("image_rect", 0) == 0;
  XmlRpc::XmlRpcValue value;
  if (!private_nh.getParam("metres_per_pixel", value))
    return;
  try
  {
    if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble)
      metres_per_pixel_ = static_cast<double>(value);
    else if (value.getType() == XmlRpc::XmlRpcValue::TypeInt)
      metres_per_pixel_ = static_cast<int>(value);
    else if (value.getType() == XmlRpc::XmlRpcValue::TypeStruct)
    {
      for (auto& entry : value)
      {
        XmlRpc::XmlRpcValue& v = entry.second;
        const double mpp = v.getType() == XmlRpc::XmlRpcValue::TypeInt ? static_cast<double>(static_cast<int>(v))
                                                                          : static_cast<double>(v);
        metres_per_pixel_by_label_[entry.first] = mpp;
      }
    }
    else
      throw XmlRpc::XmlRpcException("not a number or a map");
  }
  catch (const XmlRpc::XmlRpcException& e)
  {
    ROS_ERROR("~metres_per_pixel must be a number (m per prototype px, > 0) or a map label -> number: %s; "
              "no poses",
              e.getMessage().c_str());
    metres_per_pixel_ = 0.0;
    metres_per_pixel_by_label_.clear();
  }
  if (metres_per_pixel_ < 0.0)
  {
    ROS_ERROR("~metres_per_pixel must be > 0, got %g; no poses", metres_per_pixel_);
    metres_per_pixel_ = 0.0;
  }
}

double ObjectPoses::metresPerPixel(const std::string& label) const
{
  const auto it = metres_per_pixel_by_label_.find(label);
  return it != metres_per_pixel_by_label_.end() ? it->second : metres_per_pixel_;
}

void ObjectPoses::cameraInfoCb(const sensor_msgs::CameraInfoConstPtr& msg)
{
  try
  {
    auto camera = std::make_shared<PnpCamera>();
    std::string problem;
    if (!pnpCamera(*msg, rectified_, *camera, problem))
      camera.reset();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!problem.empty() && info_errors_.shouldReport(problem))
      ROS_ERROR("%s: no poses until a valid camera_info arrives", problem.c_str());
    camera_ = camera;
  }
  catch (...)  // nothing may leave a callback
  {
  }
}

void ObjectPoses::fill(const std::vector<amcr::RecognizedObject>& objects, const amcr::PrototypeMemory& memory,
                       amcr::Recognitions& out, PlaneOutlines* outlines)
{
  if (outlines)
    outlines->assign(out.objects.size(), {});
  if (out.objects.empty())
    return;
  std::shared_ptr<const PnpCamera> camera;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    camera = camera_;
  }
  for (std::size_t i = 0; i < out.objects.size() && i < objects.size(); ++i)
  {
    const amcr::RecognizedObject& core = objects[i];
    amcr::Recognition& object = out.objects[i];
    const double mpp = metresPerPixel(core.label);
    std::string why;
    if (!camera)
      why = "no valid camera_info received on " + camera_info_topic_;
    else if (out.header.frame_id.empty())
      why = "the image has no frame_id";
    else if (!(mpp > 0.0))
      why = "~metres_per_pixel is not set for '" + core.label + "'";
    else if (core.prototype_id >= 0 && core.prototype_id < static_cast<int>(memory.size()))
    {
      const amcr::Prototype& prototype = memory[static_cast<std::size_t>(core.prototype_id)];
      const PlanarTarget target = planarTarget(prototype, mpp);
      // The homography: a perspective view's corners where they are (the affine's lift when not used).
      object.pose_valid = planarPose(core.homography, target, *camera, object.pose, why);
      if (object.pose_valid && outlines)
        (*outlines)[i] = planeOutline(prototype, target);
    }
    if (!object.pose_valid)
    {
      ROS_WARN_THROTTLE(30.0, "no pose for recognized objects: %s", why.c_str());
      continue;
    }
    broadcast(out.header, object);
  }
}

std::vector<geometry_msgs::Point> ObjectPoses::planeOutline(const amcr::Prototype& prototype,
                                                          const PlanarTarget& target)
{
  std::vector<geometry_msgs::Point> points;
  points.reserve(prototype.outline().size());
  for (const amcr::OutlinePoint& p : prototype.outline())
  {
    const cv::Point2d original = amcr::applyAffine(prototype.tableToOriginal(), p.position);
    geometry_msgs::Point q;
    q.x = (original.x - target.origin.x) * target.metres_per_pixel;
    q.y = (original.y - target.origin.y) * target.metres_per_pixel;
    points.push_back(q);
  }
  return points;
}

void ObjectPoses::broadcast(const std_msgs::Header& header, const amcr::Recognition& object)
{
  geometry_msgs::TransformStamped t;
  t.header = header;
  t.child_frame_id = frame_prefix_ + object.label + "_" + std::to_string(object.track_id);
  t.transform.translation.x = object.pose.position.x;
  t.transform.translation.y = object.pose.position.y;
  t.transform.translation.z = object.pose.position.z;
  t.transform.rotation = object.pose.orientation;
  tf_broadcaster_.sendTransform(t);
}
}  // namespace amcr_ros
