#include "recognizer_nodelet.h"

#include <chrono>
#include <exception>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>

#include "amcr/errors.h"
#include "amcr/overlay.h"
#include "image_input.h"
#include "message_conversion.h"
#include "parameter_loading.h"
#include <amcr/PrototypeTable.h>
#include <amcr/Recognitions.h>

namespace amcr_ros
{
void RecognizerNodelet::onInit()
{
  ros::NodeHandle& nh = getNodeHandle();
  ros::NodeHandle& private_nh = getPrivateNodeHandle();
  it_ = std::make_shared<image_transport::ImageTransport>(nh);

  {
    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    try
    {
      std::vector<std::string> notes;
      params_ = loadParams(private_nh, &notes);
      for (const std::string& note : notes)
        NODELET_DEBUG("parameter: %s", note.c_str());
    }
    catch (const std::exception& e)
    {
      params_ = amcr::Params();
      NODELET_ERROR("invalid parameters, using the defaults of config/amcr.yaml instead: %s", e.what());
    }

    pub_prototypes_ = private_nh.advertise<amcr::PrototypeTable>("prototypes", 1, true);
    std::string directory;
    private_nh.param<std::string>("prototypes", directory, "");
    if (directory.empty())
      NODELET_ERROR("no prototypes: set ~prototypes to a directory of silhouette images, or call %s",
                    private_nh.resolveName("load_prototypes").c_str());
    else
    {
      const std::string error = loadPrototypes(directory);
      if (!error.empty())
        NODELET_ERROR("%s; the nodelet keeps running: call %s with a valid directory", error.c_str(),
                      private_nh.resolveName("load_prototypes").c_str());
    }
    publishPrototypeTable();
  }

  pub_recognitions_ = private_nh.advertise<amcr::Recognitions>("recognitions", 10);
  image_transport::ImageTransport private_it(private_nh);
  pub_overlay_ = private_it.advertise("overlay", 1);
  srv_reset_ = private_nh.advertiseService("reset", &RecognizerNodelet::resetCb, this);
  srv_load_ = private_nh.advertiseService("load_prototypes", &RecognizerNodelet::loadPrototypesCb, this);

  // The input is always subscribed: recognition is spread over frames, so the
  // filter must see the stream even while nobody listens yet.
  const image_transport::TransportHints hints("raw", ros::TransportHints(), private_nh);
  sub_image_ = it_->subscribe("image", 1, &RecognizerNodelet::imageCb, this, hints);
}

std::string RecognizerNodelet::loadPrototypes(const std::string& directory)
{
  try
  {
    std::vector<std::string> warnings;
    auto memory = std::make_shared<amcr::PrototypeMemory>(amcr::PrototypeMemory::loadDirectory(
        directory, params_, [&warnings](const std::string& w) { warnings.push_back(w); }));
    for (const std::string& w : warnings)
      NODELET_WARN("prototypes: %s", w.c_str());
    if (recognizer_)
      recognizer_->setMemory(memory);
    else
      recognizer_ = std::make_unique<amcr::Recognizer>(params_, memory);
    memory_ = memory;
    memory_directory_ = directory;
    last_stamp_ = ros::Time();
    NODELET_INFO("loaded %zu prototypes from '%s'", memory->size(), directory.c_str());
    return "";
  }
  catch (const std::exception& e)
  {
    return "cannot load prototypes from '" + directory + "': " + e.what();
  }
}

void RecognizerNodelet::publishPrototypeTable()
{
  pub_prototypes_.publish(toMsg(memory_.get(), memory_directory_, ros::Time::now()));
}

bool RecognizerNodelet::resetCb(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
{
  std::lock_guard<std::mutex> lock(recognizer_mutex_);
  if (recognizer_)
    recognizer_->reset();
  last_stamp_ = ros::Time();
  NODELET_INFO("filter reset");
  return true;
}

bool RecognizerNodelet::loadPrototypesCb(amcr::LoadPrototypes::Request& request,
                                         amcr::LoadPrototypes::Response& response)
{
  std::lock_guard<std::mutex> lock(recognizer_mutex_);
  response.message = loadPrototypes(request.directory);
  response.success = response.message.empty();
  response.num_prototypes = response.success ? static_cast<int>(memory_->size()) : 0;
  if (response.success)
    publishPrototypeTable();
  else
    NODELET_ERROR("%s (the previous memory stays in use)", response.message.c_str());
  return true;  // the answer carries the error: the call itself succeeded
}

void RecognizerNodelet::reportInputError(const std::string& text)
{
  std::lock_guard<std::mutex> lock(report_mutex_);
  if (input_errors_.shouldReport(text))
    NODELET_ERROR("%s", text.c_str());
}

void RecognizerNodelet::imageCb(const sensor_msgs::ImageConstPtr& msg)
{
  try
  {
    std::string why;
    cv_bridge::CvImageConstPtr image = toCoreImage(msg, why);
    if (!image)
    {
      reportInputError("image skipped: " + why);
      return;
    }

    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    if (!recognizer_)
    {
      NODELET_ERROR_THROTTLE(5.0, "no prototypes loaded: images are ignored until %s succeeds",
                             getPrivateNodeHandle().resolveName("load_prototypes").c_str());
      return;
    }
    if (!last_stamp_.isZero() && msg->header.stamp < last_stamp_)
    {
      NODELET_WARN("time went backwards (%.3f s -> %.3f s; a looped bag?): filter reset", last_stamp_.toSec(),
                   msg->header.stamp.toSec());
      recognizer_->reset();
    }
    last_stamp_ = msg->header.stamp;
    if (last_size_ != image->image.size())
    {
      if (!last_size_.empty())
        NODELET_INFO("image size changed from %d x %d to %d x %d: V-particles re-seeded", last_size_.width,
                     last_size_.height, image->image.cols, image->image.rows);
      last_size_ = image->image.size();
    }

    const auto start = std::chrono::steady_clock::now();
    const amcr::RecognitionResult result = recognizer_->step(image->image);
    amcr::Recognitions out = toMsg(result, msg->header);
    out.processing_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    pub_recognitions_.publish(out);

    if (pub_overlay_.getNumSubscribers() > 0)
    {
      cv_bridge::CvImage overlay(msg->header, sensor_msgs::image_encodings::BGR8,
                                 amcr::drawOverlay(image->image, *recognizer_, result));
      pub_overlay_.publish(overlay.toImageMsg());
    }
  }
  catch (const std::exception& e)
  {
    reportInputError("image (" + std::to_string(msg->width) + " x " + std::to_string(msg->height) + ", '" +
                     msg->encoding + "') skipped: " + e.what());
  }
}
}  // namespace amcr_ros

PLUGINLIB_EXPORT_CLASS(amcr_ros::RecognizerNodelet, nodelet::Nodelet)
