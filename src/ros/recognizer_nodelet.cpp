#include "recognizer_nodelet.h"

#include <chrono>
#include <exception>
#include <vector>

#include <cv_bridge/cv_bridge.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/image_encodings.h>
#include <xmlrpcpp/XmlRpcException.h>

#include "amcr/errors.h"
#include "amcr/overlay.h"
#include "image_input.h"
#include "message_conversion.h"
#include "planar_pose.h"
#include "reconfigure.h"
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

  loadPoseParameters();
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  sub_info_ = nh.subscribe("camera_info", 1, &RecognizerNodelet::cameraInfoCb, this);

  pub_recognitions_ = private_nh.advertise<amcr::Recognitions>("recognitions", 10);
  image_transport::ImageTransport private_it(private_nh);
  pub_overlay_ = private_it.advertise("overlay", 1);
  srv_reset_ = private_nh.advertiseService("reset", &RecognizerNodelet::resetCb, this);
  srv_load_ = private_nh.advertiseService("load_prototypes", &RecognizerNodelet::loadPrototypesCb, this);

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

  // dynamic_reconfigure starts from the parameters loaded above (~config
  // included), not from the .cfg defaults.
  amcr::AMCRConfig initial;
  {
    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    initial = toConfig(params_);
  }
  reconfigure_server_ = std::make_shared<dynamic_reconfigure::Server<amcr::AMCRConfig>>(reconfigure_mutex_, private_nh);
  reconfigure_server_->updateConfig(initial);
  reconfigure_server_->setCallback(
      [this](amcr::AMCRConfig& config, std::uint32_t level) { reconfigureCb(config, level); });

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, private_nh, getName());
  updater_->setHardwareID("none");
  updater_->add("recognizer", [this](diagnostic_updater::DiagnosticStatusWrapper& status) {
    stats_.report(status);
    status.add("overlay subscribers", pub_overlay_.getNumSubscribers());
  });
  diagnostics_timer_ = private_nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    try
    {
      updater_->update();
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(60.0, "diagnostics: %s", e.what());
    }
  });
}

void RecognizerNodelet::reconfigureCb(amcr::AMCRConfig& config, std::uint32_t level)
{
  try
  {
    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    amcr::Params changed = fromConfig(config, params_);
    changed.validate();
    if (getParameterChanges(changed).empty())
      return;  // the initial call, or nothing new
    const std::string what = getParameterChanges(changed);
    std::shared_ptr<const amcr::PrototypeMemory> memory = memory_;
    if (memory && ((level & kReconfigureTables) || tablesDiffer(changed, params_)))
      memory = std::make_shared<amcr::PrototypeMemory>(amcr::PrototypeMemory::loadDirectory(
          memory_directory_, changed, [this](const std::string& w) { NODELET_WARN("prototypes: %s", w.c_str()); }));
    const bool tables_rebuilt = memory != memory_;
    std::unique_ptr<amcr::Recognizer> rebuilt;
    if (memory)
      rebuilt = std::make_unique<amcr::Recognizer>(changed, memory);
    // Nothing failed: swap everything at once.
    params_ = changed;
    memory_ = memory;
    recognizer_ = std::move(rebuilt);
    last_stamp_ = ros::Time();
    NODELET_INFO("reconfigured (%s): %s", what.c_str(),
                 !memory_ ? "no prototypes loaded yet"
                          : tables_rebuilt ? "prototype tables and filter rebuilt" : "filter rebuilt");
  }
  catch (const std::exception& e)
  {
    NODELET_ERROR("reconfiguration refused, the previous parameters stay: %s", e.what());
    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    config = toConfig(params_);  // what is in use is what the client sees
  }
}

std::string RecognizerNodelet::getParameterChanges(const amcr::Params& changed) const
{
  std::string out;
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    const double before = amcr::getParameter(params_, info.name), after = amcr::getParameter(changed, info.name);
    if (before != after)
      out += (out.empty() ? "" : ", ") + info.name + " " + std::to_string(before) + " -> " + std::to_string(after);
  }
  if (changed.likelihood_form != params_.likelihood_form)
    out += (out.empty() ? "" : ", ") + std::string("likelihood_form ") + amcr::toString(changed.likelihood_form);
  if (changed.deviation_space != params_.deviation_space)
    out += (out.empty() ? "" : ", ") + std::string("deviation_space ") + amcr::toString(changed.deviation_space);
  return out;
}

void RecognizerNodelet::loadPoseParameters()
{
  ros::NodeHandle& private_nh = getPrivateNodeHandle();
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
    NODELET_ERROR("~metres_per_pixel must be a number (m per prototype px, > 0) or a map label -> number: %s; "
                  "no poses",
                  e.getMessage().c_str());
    metres_per_pixel_ = 0.0;
    metres_per_pixel_by_label_.clear();
  }
  if (metres_per_pixel_ < 0.0)
  {
    NODELET_ERROR("~metres_per_pixel must be > 0, got %g; no poses", metres_per_pixel_);
    metres_per_pixel_ = 0.0;
  }
}

double RecognizerNodelet::metresPerPixel(const std::string& label) const
{
  const auto it = metres_per_pixel_by_label_.find(label);
  return it != metres_per_pixel_by_label_.end() ? it->second : metres_per_pixel_;
}

void RecognizerNodelet::cameraInfoCb(const sensor_msgs::CameraInfoConstPtr& msg)
{
  const std::string problem = checkCameraInfo(*msg);
  if (!problem.empty())
    reportInputError(problem + ": no poses until a valid camera_info arrives");
  std::lock_guard<std::mutex> lock(info_mutex_);
  camera_info_ = problem.empty() ? msg : nullptr;
}

void RecognizerNodelet::fillPoses(amcr::Recognitions& out)
{
  if (out.objects.empty())
    return;
  sensor_msgs::CameraInfoConstPtr info;
  {
    std::lock_guard<std::mutex> lock(info_mutex_);
    info = camera_info_;
  }
  for (amcr::Recognition& object : out.objects)
  {
    const double mpp = metresPerPixel(object.label);
    std::string why;
    if (!info)
      why = "no valid camera_info received";
    else if (out.header.frame_id.empty())
      why = "the image has no frame_id";
    else if (!(mpp > 0.0))
      why = "~metres_per_pixel is not set for '" + object.label + "'";
    else if (object.prototype_id >= 0 && memory_ && object.prototype_id < static_cast<int>(memory_->size()))
    {
      const cv::Size size = (*memory_)[static_cast<std::size_t>(object.prototype_id)].originalSize();
      const auto& a = object.prototype_to_image;
      object.pose_valid = planarPose(amcr::Affine(a[0], a[1], a[2], a[3], a[4], a[5]), size.width, size.height, mpp,
                                     *info, object.pose, why);
    }
    if (!object.pose_valid)
    {
      NODELET_WARN_THROTTLE(30.0, "no pose for recognized objects: %s", why.c_str());
      continue;
    }
    geometry_msgs::TransformStamped t;
    t.header = out.header;
    t.child_frame_id = frame_prefix_ + object.label + "_" + std::to_string(object.track_id);
    t.transform.translation.x = object.pose.position.x;
    t.transform.translation.y = object.pose.position.y;
    t.transform.translation.z = object.pose.position.z;
    t.transform.rotation = object.pose.orientation;
    tf_broadcaster_->sendTransform(t);
  }
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
    stats_.setPrototypes(memory->size(), "");
    return "";
  }
  catch (const std::exception& e)
  {
    const std::string error = "cannot load prototypes from '" + directory + "': " + e.what();
    if (!memory_)
      stats_.setPrototypes(0, error);
    return error;
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
    stats_.received(msg->header.seq);
    std::string why;
    cv_bridge::CvImageConstPtr image = toCoreImage(msg, why);
    if (!image)
    {
      stats_.skipped();
      reportInputError("image skipped: " + why);
      return;
    }

    std::lock_guard<std::mutex> lock(recognizer_mutex_);
    if (!recognizer_)
    {
      stats_.skipped();
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
    fillPoses(out);
    pub_recognitions_.publish(out);
    stats_.processed(out, {result.converged_v_particles, params_.num_v_particles, result.flow_failures,
                           params_.frame_budget_ms});

    if (pub_overlay_.getNumSubscribers() > 0)
    {
      cv_bridge::CvImage overlay(msg->header, sensor_msgs::image_encodings::BGR8,
                                 amcr::drawOverlay(image->image, *recognizer_, result));
      pub_overlay_.publish(overlay.toImageMsg());
      stats_.overlayDrawn();
    }
  }
  catch (const std::exception& e)
  {
    stats_.skipped();
    try
    {
      reportInputError("image (" + std::to_string(msg->width) + " x " + std::to_string(msg->height) + ", '" +
                       msg->encoding + "') skipped: " + e.what());
    }
    catch (...)  // nothing may leave a callback: it would take the manager down
    {
    }
  }
  catch (...)
  {
    stats_.skipped();
    NODELET_ERROR_THROTTLE(5.0, "image skipped: unknown error");
  }
}
}  // namespace amcr_ros

PLUGINLIB_EXPORT_CLASS(amcr_ros::RecognizerNodelet, nodelet::Nodelet)
