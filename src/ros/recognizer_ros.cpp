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
#include <std_srvs/Trigger.h>

#include "amcr/base/parallel_for.h"
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

/// Lowers the CPU priority of the thread that serves its queue, of it alone (Linux: a thread's niceness).
class LowerThreadPriority : public ros::CallbackInterface
{
  CallResult call() override
  {
    if (setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kRebuildNiceness) != 0)
      ROS_WARN("cannot lower the priority of the rebuild thread (%s): a rebuild competes with the images for CPU",
               std::strerror(errno));
    return Success;
  }
};

/// A service's callback that answers with `answer(request)`, which carries any error: the call succeeds.
template <typename Service, typename Answer>
auto answering(Answer answer)
{
  return [answer](typename Service::Request& request, typename Service::Response& response) {
    response = answer(request);
    return true;
  };
}
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
  amcr::Params params;
  try
  {
    std::vector<std::string> notes;
    params = loadParams(private_nh_, &notes);
    for (const std::string& note : notes)
      ROS_DEBUG("parameter: %s", note.c_str());
  }
  catch (const std::exception& e)  // `params` keeps the defaults
  {
    ROS_ERROR("invalid parameters, using the defaults of config/amcr.yaml instead: %s", e.what());
  }
  session_ = std::make_unique<amcr::RecognizerSession>(params, sessionHooks());

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
  std::string directory;
  private_nh_.param<std::string>("prototypes", directory, "");
  if (directory.empty())
    ROS_ERROR("no prototypes: set ~prototypes to a directory of silhouette images, or call %s",
              private_nh_.resolveName("load_prototypes").c_str());
  else
  {
    PreparedSwap prepared = prepareLoad(directory);  // on this thread and amcr's workers: nothing to wait for
    const std::string error = commit(prepared);
    if (!error.empty())
    {
      stats_.setPrototypes(0, error);
      ROS_ERROR("%s; the nodelet keeps running: call %s with a valid directory", error.c_str(),
                private_nh_.resolveName("load_prototypes").c_str());
    }
  }
  const amcr::LabelTable table = session_->labelTable();
  if (!table.memory)
    publishPrototypeTable(table);  // the empty table (a load publishes its own)
}

amcr::SessionHooks RecognizerRos::sessionHooks()
{
  amcr::SessionHooks hooks;
  hooks.warning = [](const std::string& text) { ROS_WARN("%s", text.c_str()); };
  hooks.info = [](const std::string& text) { ROS_INFO("%s", text.c_str()); };
  hooks.restarted = [this] { stats_.restarted(); };
  hooks.table_changed = [this](const amcr::LabelTable& table) {
    stats_.setPrototypes(table.memory ? table.memory->size() : 0, "");
    publishPrototypeTable(table);
  };
  return hooks;
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
  input_status_.addTask(&input_rate_);
  input_status_.addTask(&input_delay_);
  updater_->add(input_status_);
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
      "reset", answering<std_srvs::Trigger>([this](const std_srvs::Trigger::Request&) {
        std_srvs::Trigger::Response response;
        response.message = reset();
        response.success = true;
        return response;
      }));
  srv_load_ = edit_nh.advertiseService<amcr::LoadPrototypes::Request, amcr::LoadPrototypes::Response>(
      "load_prototypes",
      answering<amcr::LoadPrototypes>([this](const auto& request) { return loadPrototypes(request.directory); }));
  srv_teach_ = edit_nh.advertiseService<amcr::TeachPrototype::Request, amcr::TeachPrototype::Response>(
      "teach", answering<amcr::TeachPrototype>([this](const auto& request) { return teach(request); }));
  srv_remove_ = edit_nh.advertiseService<amcr::RemovePrototype::Request, amcr::RemovePrototype::Response>(
      "remove_prototype", answering<amcr::RemovePrototype>([this](const auto& r) { return removePrototype(r.label); }));
  // amcr's workers (the images' parallelFor loops) and OpenCV's start here, at the host's priority: started
  // later by the rebuild thread, they would inherit its lower one.
  amcr::startWorkerThreads();
  edit_queue_.addCallback(boost::make_shared<LowerThreadPriority>());
  edit_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &edit_queue_);
  edit_spinner_->start();
}

std::string RecognizerRos::reset()
{
  const std::string what = session_->reset();
  ROS_INFO("%s", what.c_str());
  return what;
}

bool RecognizerRos::process(const sensor_msgs::ImageConstPtr& msg, bool draw_overlay, Frame& frame)
{
  try
  {
    stats_.received(msg->header.seq);
    input_rate_.tick();
    input_delay_.tick(msg->header.stamp);
    std::string why;
    cv_bridge::CvImageConstPtr image = toCoreImage(msg, why);
    if (!image)
    {
      stats_.skipped();
      reportInputError("image skipped: " + why);
      return false;
    }

    std::lock_guard<std::mutex> lock(input_mutex_);
    amcr::FrameInput input;
    input.image = image->image;  // may view the message's buffer: the session keeps `image` with it (~teach)
    input.pixels_owner = std::shared_ptr<const void>(image.get(), [image](const void*) {});
    input.draw_overlay = draw_overlay;
    input.restart_unless_fresh = !last_stamp_.isZero() && msg->header.stamp < last_stamp_;
    amcr::RecognizedFrame& out = frame;
    out = session_->recognize(input);
    if (!out.recognized && out.error.empty())
    {
      stats_.skipped();
      ROS_ERROR_THROTTLE(5.0, "no prototypes loaded: images are ignored until %s succeeds",
                         private_nh_.resolveName("load_prototypes").c_str());
      return false;
    }
    if (out.input_restart)
      ROS_WARN("time went backwards (%.3f s -> %.3f s; a looped bag?): filter reset", last_stamp_.toSec(),
               msg->header.stamp.toSec());
    last_stamp_ = msg->header.stamp;
    if (!out.recognized)
    {
      reportSkipped(*msg, out.error);
      return false;
    }
    frame.message = toMsg(out.result, msg->header);
    frame.message.prototype_table_version = out.table_version;
    RecognizerStats::FilterState state;  // by name: positional braces once swapped the budget and the M-particle mean
    state.converged_v_particles = out.result.converged_v_particles;
    state.num_v_particles = out.params->num_v_particles;
    state.flow_failures = out.result.flow_failures;
    state.mean_m_particles = out.result.mean_m_particles;
    state.budget_ms = out.params->frame_budget_ms;
    state.objects_over_limit = out.result.objects_over_limit;
    state.max_objects = out.params->max_objects;
    stats_.processed(frame.message, state);
    if (!out.overlay.empty())
      stats_.overlayDrawn();
    if (!out.overlay_error.empty())  // the recognitions stand
      reportSkipped(*msg, out.overlay_error);
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

void RecognizerRos::publishPrototypeTable(const amcr::LabelTable& table)
{
  pub_prototypes_.publish(toMsg(table.memory.get(), table.directory, table.version, ros::Time::now()));
}

void RecognizerRos::reportInputError(const std::string& text)
{
  std::lock_guard<std::mutex> lock(report_mutex_);
  if (input_errors_.shouldReport(text))
    ROS_ERROR("%s", text.c_str());
}
}  // namespace amcr_ros
