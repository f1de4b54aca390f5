// The recognizer as a ROS component, without the nodelet: an amcr::RecognizerSession (parameters,
// memory, recognizer, the rebuilds beside the images and their swap; amcr/recognizer_session.h) served
// through ROS, built from plain node handles so that a test can drive it (test/test_recognizer_ros.cpp).
// Here: cv_bridge, the messages, the services, dynamic_reconfigure, /diagnostics, the latched
// ~prototypes table, the ROS logs of the session's news and the input's time (going backwards restarts
// the filter); the nodelet (recognizer_nodelet.h, which lists them all) adds the images and outputs.
// The rebuilding calls and dynamic_reconfigure are served on a thread of their own at a lower CPU
// priority, where the session builds alone: a nodelet's queue goes on delivering images, which go first.
// No method throws (prepare*() and commit() included).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <boost/thread/recursive_mutex.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <dynamic_reconfigure/server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <sensor_msgs/Image.h>

#include "amcr/recognizer_session.h"
#include "recognizer_stats.h"
#include "report_throttle.h"
#include <amcr/AMCRConfig.h>
#include <amcr/LoadPrototypes.h>
#include <amcr/Recognitions.h>
#include <amcr/RemovePrototype.h>
#include <amcr/TeachPrototype.h>

namespace amcr_ros
{
class RecognizerRos
{
public:
  /// Reads the parameters (invalid ones are logged and the defaults used), loads ~prototypes when set
  /// (a failure is logged: images are skipped until a load succeeds) and advertises the services.
  /// `overlay_subscribers` counts the subscribers of the overlay for /diagnostics (none when empty).
  RecognizerRos(ros::NodeHandle nh, ros::NodeHandle private_nh,
                std::function<std::uint32_t()> overlay_subscribers = {});

  /// What one image gave: the session's frame (result, memory, overlay, restart) and its message.
  struct Frame : amcr::RecognizedFrame
  {
    amcr::Recognitions message;  ///< the result with the image's header; no poses yet
  };

  /// Runs the recognizer on one image (and draws the overlay when `draw_overlay`); an image older than
  /// the last restarts the filter first. False when the image was skipped: bad input or no prototypes,
  /// logged (throttled) and counted.
  bool process(const sensor_msgs::ImageConstPtr& msg, bool draw_overlay, Frame& frame);

  /// ~reset: the filter starts again from the next image. Returns what was done.
  std::string reset();
  /// ~load_prototypes, ~teach, ~remove_prototype: the session's load(), teach() (of the request's
  /// polygon, or its rectangle when the polygon has no points) and remove(), their refusals logged.
  amcr::LoadPrototypes::Response loadPrototypes(const std::string& directory);
  amcr::TeachPrototype::Response teach(const amcr::TeachPrototype::Request& request);
  amcr::RemovePrototype::Response removePrototype(const std::string& label);
  /// The label table's version (amcr/PrototypeTable.version).
  std::uint32_t tableVersion() const { return session_->tableVersion(); }
  amcr::Params params() const { return session_->params(); }

  /// dynamic_reconfigure: rebuilds the filter (and the tables when `level` or the parameters ask for it)
  /// with `config`. Returns the error (naming the parameter, its value and range), empty on success; on
  /// an error nothing changes. Either way `config` becomes the configuration in effect, so that the
  /// server never shows a value that is not (and a refused value cannot spoil the next change).
  std::string reconfigure(amcr::AMCRConfig& config, std::uint32_t level);

  /// ~load_prototypes and reconfigure() in their two steps (RecognizerSession's).
  using PreparedSwap = amcr::RecognizerSession::PreparedSwap;
  PreparedSwap prepareLoad(const std::string& directory) { return session_->prepareLoad(directory); }
  PreparedSwap prepareReconfigure(const amcr::AMCRConfig& config, std::uint32_t level);
  std::string commit(PreparedSwap& prepared) { return session_->commit(prepared); }
  static constexpr const char* kMemoryChanged = amcr::RecognizerSession::kMemoryChanged;

  /// An image that failed after process() returned (publishing): logged and counted as skipped.
  void reportSkipped(const sensor_msgs::Image& msg, const std::string& why);

private:
  /// The parameters, the session and the memory of ~prototypes, logged when invalid.
  void loadStartupState();
  /// The reconfigure server, /diagnostics and the services.
  void advertise(std::function<std::uint32_t()> overlay_subscribers);
  /// The session's news: logged, counted in the statistics, the label table published.
  amcr::SessionHooks sessionHooks();
  void publishPrototypeTable(const amcr::LabelTable& table);
  /// An error about an input, at most every 5 s per distinct text.
  void reportInputError(const std::string& text);

  ros::NodeHandle nh_, private_nh_;
  ros::Publisher pub_prototypes_;
  RecognizerStats stats_;
  std::mutex report_mutex_;
  ReportThrottle input_errors_{5.0};  // per problem text, seconds

  std::unique_ptr<amcr::RecognizerSession> session_;  // its hooks use the members above
  std::mutex input_mutex_;  // one image at a time, its time checked with its step
  ros::Time last_stamp_;    // of the last image recognized

  // Last: their callbacks use everything above. The queue of the rebuilding calls outlives their servers.
  ros::CallbackQueue edit_queue_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<amcr::AMCRConfig>> reconfigure_server_;
  double min_input_rate_ = 1.0, max_input_rate_ = 0.0;  // Hz; read by the frequency status
  diagnostic_updater::FrequencyStatus input_rate_{{&min_input_rate_, &max_input_rate_}};
  diagnostic_updater::TimeStampStatus input_delay_;
  diagnostic_updater::CompositeDiagnosticTask input_status_{"input images"};  // the two above
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diagnostics_timer_;
  ros::ServiceServer srv_reset_, srv_load_, srv_teach_, srv_remove_;
  std::unique_ptr<ros::AsyncSpinner> edit_spinner_;  // stopped first: no rebuild runs past the members
};
}  // namespace amcr_ros
