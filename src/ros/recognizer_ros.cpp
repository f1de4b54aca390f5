#include "recognizer_ros.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <limits>
#include <vector>

#include <boost/make_shared.hpp>
#include <cv_bridge/cv_bridge.h>

#include "amcr/base/parallel_for.h"
#include "amcr/overlay.h"
#include "image_input.h"
#include "message_conversion.h"
#include "parameter_loading.h"
#include "reconfigure.h"
#include <amcr/PrototypeTable.h>

namespace amcr_ros
{
namespace
{
/// Niceness of the thread that serves the rebuilding calls: the images go first, a rebuild takes the CPU
/// they leave (on a saturated CPU it takes longer, and the output keeps its rate).
constexpr int kRebuildNiceness = 10;

/// Lowers the CPU priority of the calling thread alone (Linux: a thread's own niceness).
void lowerThisThreadsPriority()
{
  const auto thread = static_cast<id_t>(syscall(SYS_gettid));
  if (setpriority(PRIO_PROCESS, thread, kRebuildNiceness) != 0)
    ROS_WARN("cannot lower the priority of the rebuild thread (%s): a rebuild competes with the images for CPU",
             std::strerror(errno));
}

/// A callback that runs a function once, on the thread that serves its queue.
class RunOnce : public ros::CallbackInterface
{
public:
  explicit RunOnce(std::function<void()> function) : function_(std::move(function)) {}
  CallResult call() override
  {
    function_();
    return Success;
  }

private:
  std::function<void()> function_;
};
}  // namespace

RecognizerRos::RecognizerRos(ros::NodeHandle nh, ros::NodeHandle private_nh,
                             std::function<std::uint32_t()> overlay_subscribers)
  : nh_(nh), private_nh_(private_nh)
{
  loadStartupState();
  advertise(std::move(overlay_subscribers));
}

void RecognizerRos::loadStartupState()
{
  std::unique_lock<std::mutex> lock(mutex_);
  try
  {
    std::vector<std::string> notes;
    params_ = loadParams(private_nh_, &notes);
    for (const std::string& note : notes)
      ROS_DEBUG("parameter: %s", note.c_str());
  }
  catch (const std::exception& e)
  {
    params_ = amcr::Params();
    ROS_ERROR("invalid parameters, using the defaults of config/amcr.yaml instead: %s", e.what());
  }

  private_nh_.param("min_input_rate", min_input_rate_, 1.0);
  private_nh_.param("max_input_rate", max_input_rate_, 0.0);
  if (!(min_input_rate_ >= 0.0) || !(max_input_rate_ >= 0.0))
  {
    ROS_ERROR("~min_input_rate and ~max_input_rate must be >= 0 Hz, got %g and %g: using 1 and 0 (no upper bound)",
              min_input_rate_, max_input_rate_);
    min_input_rate_ = 1.0;
    max_input_rate_ = 0.0;
  }
  if (max_input_rate_ <= 0.0)
    max_input_rate_ = std::numeric_limits<double>::infinity();

  pub_prototypes_ = private_nh_.advertise<amcr::PrototypeTable>("prototypes", 1, true);
  lock.unlock();  // the load builds without it, as every load does
  std::string directory;
  private_nh_.param<std::string>("prototypes", directory, "");
  if (directory.empty())
    ROS_ERROR("no prototypes: set ~prototypes to a directory of silhouette images, or call %s",
              private_nh_.resolveName("load_prototypes").c_str());
  else
  {
    PreparedSwap prepared = prepareLoad(directory);
    const std::string error = commit(prepared);
    if (!error.empty())
    {
      stats_.setPrototypes(0, error);
      ROS_ERROR("%s; the nodelet keeps running: call %s with a valid directory", error.c_str(),
                private_nh_.resolveName("load_prototypes").c_str());
    }
  }
  lock.lock();
  if (!memory_)
    publishPrototypeTable();  // the empty table (a load publishes its own)
}

void RecognizerRos::advertise(std::function<std::uint32_t()> overlay_subscribers)
{
  // The calls that rebuild are served on a thread of their own (edit_queue_): a build takes seconds, and
  // a nodelet's callbacks run one at a time, so on its queue a build would hold up the images.
  ros::NodeHandle edit_nh(private_nh_);
  edit_nh.setCallbackQueue(&edit_queue_);
  // dynamic_reconfigure starts from the parameters loaded above (~config included), not from the .cfg defaults.
  reconfigure_server_ =
      std::make_unique<dynamic_reconfigure::Server<amcr::AMCRConfig>>(reconfigure_mutex_, edit_nh);
  // The .cfg's bounds are open (the Server would clamp to them); clients are shown the core's ranges.
  const ConfigBounds bounds = reconfigureBounds();
  reconfigure_server_->setConfigMin(bounds.min);
  reconfigure_server_->setConfigMax(bounds.max);
  reconfigure_server_->updateConfig(toConfig(params()));
  reconfigure_server_->setCallback(
      [this](amcr::AMCRConfig& config, std::uint32_t level) { reconfigure(config, level); });

  updater_ = std::make_unique<diagnostic_updater::Updater>(nh_, private_nh_, private_nh_.getNamespace());
  updater_->setHardwareID("none");
  updater_->add("recognizer", [this, overlay_subscribers](diagnostic_updater::DiagnosticStatusWrapper& status) {
    stats_.report(status);
    status.add("overlay subscribers", overlay_subscribers ? overlay_subscribers() : 0u);
  });
  // The image stream through diagnostic_updater's standard tasks: its rate against the accepted
  // bounds, and how old the images are when they arrive.
  input_rate_ = std::make_unique<diagnostic_updater::FrequencyStatus>(
      diagnostic_updater::FrequencyStatusParam(&min_input_rate_, &max_input_rate_));
  input_delay_ = std::make_unique<diagnostic_updater::TimeStampStatus>();
  input_status_ = std::make_unique<diagnostic_updater::CompositeDiagnosticTask>("input images");
  input_status_->addTask(input_rate_.get());
  input_status_->addTask(input_delay_.get());
  updater_->add(*input_status_);
  diagnostics_timer_ = private_nh_.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    try
    {
      updater_->update();
    }
    catch (const std::exception& e)
    {
      ROS_ERROR_THROTTLE(60.0, "diagnostics: %s", e.what());
    }
  });

  srv_reset_ = private_nh_.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
      "reset", [this](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
        response.message = reset();
        response.success = true;
        return true;
      });
  srv_load_ = edit_nh.advertiseService<amcr::LoadPrototypes::Request, amcr::LoadPrototypes::Response>(
      "load_prototypes", [this](amcr::LoadPrototypes::Request& request, amcr::LoadPrototypes::Response& response) {
        response = loadPrototypes(request.directory);
        return true;  // the answer carries the error: the call itself succeeded
      });
  srv_teach_ = edit_nh.advertiseService<amcr::TeachPrototype::Request, amcr::TeachPrototype::Response>(
      "teach", [this](amcr::TeachPrototype::Request& request, amcr::TeachPrototype::Response& response) {
        response = teach(request);
        return true;
      });
  srv_remove_ = edit_nh.advertiseService<amcr::RemovePrototype::Request, amcr::RemovePrototype::Response>(
      "remove_prototype",
      [this](amcr::RemovePrototype::Request& request, amcr::RemovePrototype::Response& response) {
        response = removePrototype(request.label);
        return true;
      });
  // amcr's workers (the images' parallelFor loops) and OpenCV's (its loops within resize, blur, flow...)
  // are started here, at the host's priority: started later by the rebuild thread, they would inherit its
  // lower one.
  amcr::startWorkerThreads();
  edit_queue_.addCallback(boost::make_shared<RunOnce>(lowerThisThreadsPriority));
  edit_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &edit_queue_);
  edit_spinner_->start();
}

std::unique_ptr<amcr::Recognizer> RecognizerRos::restart(std::unique_ptr<amcr::Recognizer> replacement)
{
  if (replacement)
    std::swap(recognizer_, replacement);
  else if (recognizer_)
    recognizer_->reset();
  last_stamp_ = ros::Time();
  fresh_ = true;
  stats_.restarted();
  return replacement;
}

std::string RecognizerRos::reset()
{
  std::lock_guard<std::mutex> lock(mutex_);
  restart();
  const std::string what = recognizer_ ? "filter reset: it starts again from the next image"
                                       : "no prototypes loaded: the filter starts once they are";
  ROS_INFO("%s", what.c_str());
  return what;
}

amcr::Params RecognizerRos::params() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return params_;
}

void RecognizerRos::followInput(const ros::Time& stamp, const cv::Size& size)
{
  if (!last_stamp_.isZero() && stamp < last_stamp_)
  {
    ROS_WARN("time went backwards (%.3f s -> %.3f s; a looped bag?): filter reset", last_stamp_.toSec(),
             stamp.toSec());
    restart();
  }
  last_stamp_ = stamp;
  if (last_size_ != size)
  {
    if (!last_size_.empty())  // the recognizer re-seeds its V-particles itself
      ROS_INFO("image size changed from %d x %d to %d x %d: V-particles re-seeded", last_size_.width,
               last_size_.height, size.width, size.height);
    last_size_ = size;
  }
}

bool RecognizerRos::process(const sensor_msgs::ImageConstPtr& msg, bool draw_overlay, Frame& frame)
{
  try
  {
    stats_.received(msg->header.seq);
    input_rate_->tick();
    input_delay_->tick(msg->header.stamp);
    std::string why;
    cv_bridge::CvImageConstPtr image = toCoreImage(msg, why);
    if (!image)
    {
      stats_.skipped();
      reportInputError("image skipped: " + why);
      return false;
    }

    std::lock_guard<std::mutex> lock(mutex_);
    last_image_ = image;  // what ~teach cuts from, also before any prototype is there
    if (!recognizer_)
    {
      stats_.skipped();
      ROS_ERROR_THROTTLE(5.0, "no prototypes loaded: images are ignored until %s succeeds",
                         private_nh_.resolveName("load_prototypes").c_str());
      return false;
    }
    followInput(msg->header.stamp, image->image.size());
    frame.result = recognizer_->step(image->image);
    frame.message = toMsg(frame.result, msg->header);
    frame.message.prototype_table_version = table_version_;
    frame.memory = memory_;
    frame.restarted = fresh_;
    fresh_ = false;
    RecognizerStats::FilterState state;  // by name: positional braces once swapped the budget and the M-particle mean
    state.converged_v_particles = frame.result.converged_v_particles;
    state.num_v_particles = params_.num_v_particles;
    state.flow_failures = frame.result.flow_failures;
    state.mean_m_particles = frame.result.mean_m_particles;
    state.budget_ms = params_.frame_budget_ms;
    state.objects_over_limit = frame.result.objects_over_limit;
    state.max_objects = params_.max_objects;
    stats_.processed(frame.message, state);
    if (draw_overlay)
    {
      try
      {
        frame.overlay = amcr::drawOverlay(image->image, *recognizer_, frame.result);
        stats_.overlayDrawn();
      }
      catch (const std::exception& e)  // the recognitions stand
      {
        reportSkipped(*msg, e.what());
      }
    }
    return true;
  }
  catch (const std::exception& e)
  {
    reportSkipped(*msg, e.what());
  }
  catch (...)
  {
    stats_.skipped();
    ROS_ERROR_THROTTLE(5.0, "image skipped: unknown error");
  }
  return false;
}

void RecognizerRos::reportSkipped(const sensor_msgs::Image& msg, const std::string& why)
{
  stats_.skipped();
  try
  {
    reportInputError("image (" + std::to_string(msg.width) + " x " + std::to_string(msg.height) + ", '" +
                     msg.encoding + "') skipped: " + why);
  }
  catch (...)  // nothing may leave a callback: it would take the manager down
  {
  }
}

void RecognizerRos::publishPrototypeTable()
{
  pub_prototypes_.publish(toMsg(memory_.get(), edits_.directory(), table_version_, ros::Time::now()));
}

void RecognizerRos::reportInputError(const std::string& text)
{
  std::lock_guard<std::mutex> lock(report_mutex_);
  if (input_errors_.shouldReport(text))
    ROS_ERROR("%s", text.c_str());
}
}  // namespace amcr_ros
