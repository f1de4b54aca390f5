#include "recognizer_nodelet.h"

#include "object_markers.h"

#include <exception>

#include <cv_bridge/cv_bridge.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>

namespace amcr_ros
{
void RecognizerNodelet::onInit()
{
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& private_nh = getPrivateNodeHandle();
  it_ = std::make_shared<image_transport::ImageTransport>(nh);
  image_transport::ImageTransport private_it(private_nh);
  pub_overlay_ = private_it.advertise("overlay", 1);
  pub_recognitions_ = private_nh.advertise<amcr::Recognitions>("recognitions", 10);
  pub_markers_ = private_nh.advertise<visualization_msgs::MarkerArray>("markers", 10);
  recognizer_ = std::make_unique<RecognizerRos>(nh, private_nh, [this] { return pub_overlay_.getNumSubscribers(); });
  poses_ = std::make_unique<ObjectPoses>(nh, private_nh, nh.resolveName("image"));

  // The input is always subscribed: recognition is spread over frames, so the
  // filter must see the stream even while nobody listens yet.
  const image_transport::TransportHints hints("raw", ros::TransportHints(), private_nh);
  int queue_size = 1;
  private_nh.param("queue_size", queue_size, 1);
  if (queue_size < 1)
  {
    NODELET_ERROR("~queue_size must be >= 1, got %d: using 1", queue_size);
    queue_size = 1;
  }
  sub_image_ = it_->subscribe("image", static_cast<std::uint32_t>(queue_size), &RecognizerNodelet::imageCb, this, hints);
}

void RecognizerNodelet::imageCb(const sensor_msgs::ImageConstPtr& msg)
{
  try
  {
    RecognizerRos::Frame frame;
    if (!recognizer_->process(msg, pub_overlay_.getNumSubscribers() > 0, frame))
      return;  // reported and counted
    ObjectPoses::PlaneOutlines outlines;
    poses_->fill(frame.result.objects, *frame.memory, frame.message, &outlines);
    pub_recognitions_.publish(frame.message);
    if (pub_markers_.getNumSubscribers() > 0)
      pub_markers_.publish(objectMarkers(frame.message, outlines, frame.restarted));
    if (!frame.overlay.empty())
      pub_overlay_.publish(cv_bridge::CvImage(msg->header, sensor_msgs::image_encodings::BGR8, frame.overlay).toImageMsg());
  }
  catch (const std::exception& e)  // nothing may leave a callback: it would take the manager down
  {
    recognizer_->reportSkipped(*msg, e.what());
  }
  catch (...)
  {
    NODELET_ERROR_THROTTLE(5.0, "image skipped: unknown error");
  }
}
}  // namespace amcr_ros

PLUGINLIB_EXPORT_CLASS(amcr_ros::RecognizerNodelet, nodelet::Nodelet)
