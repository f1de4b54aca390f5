// The recognizer as a ROS component, without the nodelet: parameters, the
// prototype memory, the amcr::Recognizer, reset, reload and reconfiguration,
// all under one lock, constructed from plain node handles (so that a test can
// drive it, test/ros/test_recognizer_ros.cpp). The nodelet
// (recognizer_nodelet.h) adds the image subscription and the output topics.
//
// Advertises (private): ~prototypes (amcr/PrototypeTable, latched, with its version), ~reset
//                       (std_srvs/Trigger), ~load_prototypes (amcr/LoadPrototypes), ~teach
//                       (amcr/TeachPrototype), ~remove_prototype (amcr/RemovePrototype),
//                       dynamic_reconfigure (cfg/AMCR.cfg), and on /diagnostics the "recognizer" status
//                       and the "input images" status (diagnostic_updater's FrequencyStatus and
//                       TimeStampStatus of the image stream).
// Parameters (private): ~prototypes (directory), ~config (YAML file), every key of config/amcr.yaml,
//                       ~min_input_rate and ~max_input_rate (Hz, the input rate /diagnostics accepts;
//                       default 1 and 0 = no upper bound).
//
// Every reset goes through restart(): ~reset, a reload of the memory, a
// reconfiguration, ~remove_prototype and time going backwards in the input
// all call it; ~teach does not (the taught prototype joins the running
// filter). No method throws.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <boost/thread/recursive_mutex.hpp>
#include <cv_bridge/cv_bridge.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <opencv2/core.hpp>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <diagnostic_updater/update_functions.h>
#include <std_srvs/Trigger.h>

#include "amcr/params.h"
#include "amcr/prototype_memory.h"
#include "amcr/recognizer.h"
#include "recognizer_stats.h"
#include "report_throttle.h"
#include <amcr/AMCRConfig.h>
#include <amcr/LoadPrototypes.h>
#include <amcr/RemovePrototype.h>
#include <amcr/TeachPrototype.h>
#include <amcr/Recognitions.h>

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

  /// What one image gave.
  struct Frame
  {
    amcr::RecognitionResult result;  ///< the core's result: objects best score first, its time_ms
    amcr::Recognitions message;      ///< the same with the image's header; no poses yet
    std::shared_ptr<const amcr::PrototypeMemory> memory;  ///< the memory the objects refer to
    cv::Mat overlay;                 ///< bgr8, only when asked for
    bool restarted = false;          ///< the first image since the filter (re)started
  };

  /// Runs the recognizer on one image (and draws the overlay when `draw_overlay`). False when the
  /// image was skipped: bad input or no prototypes, logged (throttled) and counted.
  bool process(const sensor_msgs::ImageConstPtr& msg, bool draw_overlay, Frame& frame);

  /// ~reset: the filter starts again from the next image. Returns what was done.
  std::string reset();
  /// ~load_prototypes: loads a memory and swaps it in (the filter restarts), or keeps the previous one
  /// and says why. Publishes the label table on success.
  amcr::LoadPrototypes::Response loadPrototypes(const std::string& directory);
  /// ~teach: cuts the shape inside the request's region of the last image (amcr::cutShape) and adds
  /// it as a prototype of a new label to the running filter (no restart); saves it to the prototype
  /// directory when asked. On failure nothing changes and the answer says why.
  amcr::TeachPrototype::Response teach(const amcr::TeachPrototype::Request& request);
  /// ~remove_prototype: removes every prototype of a label (the filter restarts). On failure nothing
  /// changes and the answer says why.
  amcr::RemovePrototype::Response removePrototype(const std::string& label);
  /// The label table's version (amcr/PrototypeTable.version).
  std::uint32_t tableVersion() const;

  /// dynamic_reconfigure: rebuilds the filter (and the tables when `level` or the parameters ask for it)
  /// with `config`. Returns the error (naming the parameter, its value and range), empty on success; on
  /// an error nothing changes. Either way `config` becomes the configuration in effect, so that the
  /// server never shows a value that is not (and a refused value cannot spoil the next change).
  std::string reconfigure(amcr::AMCRConfig& config, std::uint32_t level);

  /// An image that failed after process() returned (publishing): logged and counted as skipped.
  void reportSkipped(const sensor_msgs::Image& msg, const std::string& why);

  amcr::Params params() const;

private:
  /// The parameters and the memory of ~prototypes, logged when invalid; publishes the label table.
  void loadStartupState();
  /// The reconfigure server, /diagnostics and the services.
  void advertise(std::function<std::uint32_t()> overlay_subscribers);
  /// The one reset path (lock held): `replacement` (a new filter, fresh by construction) takes the
  /// place of the current one, or the current one is reset; the input's time and the statistics'
  /// frame sequence start again.
  void restart(std::unique_ptr<amcr::Recognizer> replacement = nullptr);
  /// reconfigure() under the lock: throws when `config` is refused, before anything changes.
  void applyConfigLocked(const amcr::AMCRConfig& config, std::uint32_t level);
  /// PrototypeMemory::loadDirectory with its skipped files logged as warnings and its progress as info.
  static amcr::PrototypeMemory loadDirectory(const std::string& directory, const amcr::Params& params);
  /// Loads a memory and swaps it in (lock held). Returns the error text, empty on success.
  std::string loadLocked(const std::string& directory);
  /// The memory of memory_directory_ (none when empty) built with `params`, with this session's edits
  /// applied: labels removed, prototypes taught and not saved added (lock held). Throws MemoryError.
  std::shared_ptr<const amcr::PrototypeMemory> rebuildMemory(const amcr::Params& params) const;
  /// Swaps in an edited `memory` (lock held): extended (the filter goes on) or not (it restarts);
  /// the version counts up and the table is published.
  void swapEditedMemory(std::shared_ptr<const amcr::PrototypeMemory> memory, bool extended);
  /// teach(): the reason of a refusal, empty on success (then `response` is filled). Takes the lock to
  /// check the request and copy what the cut needs, cuts the shape and builds its table without it
  /// (images go on being recognized), and takes it again to swap the memory in.
  std::string teachShape(const amcr::TeachPrototype::Request& request, amcr::TeachPrototype::Response& response);
  /// Resets when time goes backwards in the input; notes a change of image size (lock held).
  void followInput(const ros::Time& stamp, const cv::Size& size);
  void publishPrototypeTable();  // lock held
  /// An error about an input, at most every 5 s per distinct text.
  void reportInputError(const std::string& text);

  ros::NodeHandle nh_, private_nh_;
  ros::Publisher pub_prototypes_;
  RecognizerStats stats_;

  std::mutex report_mutex_;
  ReportThrottle input_errors_{5.0};  // per problem text, seconds

  mutable std::mutex mutex_;  // everything below
  amcr::Params params_;
  std::shared_ptr<const amcr::PrototypeMemory> memory_;
  std::string memory_directory_;
  std::unique_ptr<amcr::Recognizer> recognizer_;  // null while no memory is loaded
  ros::Time last_stamp_;
  cv::Size last_size_;
  bool fresh_ = true;   // no image processed since restart()
  // The last image the core saw (~teach cuts from it). The pointer, not its cv::Mat: the Mat may
  // share the message's buffer, which the pointer keeps alive.
  cv_bridge::CvImageConstPtr last_image_;
  std::uint32_t table_version_ = 0;
  /// Prototypes taught in this session and not saved (kept over a rebuild of the tables), and labels
  /// removed from the directory's memory; both forgotten by ~load_prototypes.
  struct TaughtShape
  {
    std::string label;
    cv::Mat silhouette;
  };
  std::vector<TaughtShape> taught_;
  std::vector<std::string> removed_labels_;

  // Last: their callbacks use everything above.
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<amcr::AMCRConfig>> reconfigure_server_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  double min_input_rate_ = 1.0, max_input_rate_ = 0.0;  // Hz; read by the frequency status
  std::unique_ptr<diagnostic_updater::FrequencyStatus> input_rate_;
  std::unique_ptr<diagnostic_updater::TimeStampStatus> input_delay_;
  std::unique_ptr<diagnostic_updater::CompositeDiagnosticTask> input_status_;
  ros::WallTimer diagnostics_timer_;
  ros::ServiceServer srv_reset_, srv_load_, srv_teach_, srv_remove_;
};
}  // namespace amcr_ros
