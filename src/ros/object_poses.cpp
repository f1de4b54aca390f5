#include "object_poses.h"

#include <xmlrpcpp/XmlRpcException.h>

#include "planar_pose.h"

namespace amcr_ros
{
ObjectPoses::ObjectPoses(ros::NodeHandle nh, const ros::NodeHandle& private_nh)
{
  loadParameters(private_nh);
  sub_info_ = nh.subscribe("camera_info", 1, &ObjectPoses::cameraInfoCb, this);
}

void ObjectPoses::loadParameters(const ros::NodeHandle& private_nh)
{
  private_nh.param<std::string>("frame_prefix", frame_prefix_, "amcr/");
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
    const std::string problem = checkCameraInfo(*msg);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!problem.empty() && info_errors_.shouldReport(problem))
      ROS_ERROR("%s: no poses until a valid camera_info arrives", problem.c_str());
    camera_info_ = problem.empty() ? msg : nullptr;
  }
  catch (...)  // nothing may leave a callback
  {
  }
}

void ObjectPoses::fill(const std::vector<amcr::RecognizedObject>& objects, const amcr::PrototypeMemory& memory,
                       amcr::Recognitions& out)
{
  if (out.objects.empty())
    return;
  sensor_msgs::CameraInfoConstPtr info;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info = camera_info_;
  }
  for (std::size_t i = 0; i < out.objects.size() && i < objects.size(); ++i)
  {
    const amcr::RecognizedObject& core = objects[i];
    amcr::Recognition& object = out.objects[i];
    const double mpp = metresPerPixel(core.label);
    std::string why;
    if (!info)
      why = "no valid camera_info received";
    else if (out.header.frame_id.empty())
      why = "the image has no frame_id";
    else if (!(mpp > 0.0))
      why = "~metres_per_pixel is not set for '" + core.label + "'";
    else if (core.prototype_id >= 0 && core.prototype_id < static_cast<int>(memory.size()))
    {
      const cv::Size size = memory[static_cast<std::size_t>(core.prototype_id)].originalSize();
      // The homography: a perspective view's corners where they are (the affine's lift when not used).
      object.pose_valid = planarPose(core.homography, size.width, size.height, mpp, *info, object.pose, why);
    }
    if (!object.pose_valid)
    {
      ROS_WARN_THROTTLE(30.0, "no pose for recognized objects: %s", why.c_str());
      continue;
    }
    broadcast(out.header, object);
  }
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
