// The recognizer as a ROS component, without the nodelet: parameters, the
// prototype memory, the amcr::Recognizer, reset, reload and reconfiguration,
// constructed from plain node handles (so that a test can drive it,
// test/ros/test_recognizer_ros.cpp). The nodelet (recognizer_nodelet.h) adds
// the image subscription and the output topics.
//
// Images are recognized under one lock (mutex_). A rebuild (~load_prototypes,
// ~teach, ~remove_prototype, a reconfiguration) never builds under it: it
// copies what it needs under the lock, builds the new memory and filter
// without it while images go on being recognized with the old filter, and
// takes the lock again only to swap them in (recognizer_reload.cpp). The swap
// is refused when another one landed meanwhile (the memory generation
// changed): nothing changes and the caller is told to try again. Rebuilds run
// one at a time (rebuild_mutex_): a second call waits for the first and then
// builds on what it swapped in. Their services and dynamic_reconfigure are
// served on a thread of their own, so that the host's callback queue (a
// nodelet's runs one callback at a time) goes on delivering images meanwhile;
// that thread runs at a lower CPU priority and builds on itself alone
// (amcr::SingleThreadScope): its work stays at that priority instead of going
// to amcr's workers, which run the images' loops at the host's, so the images
// go first.
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
// filter). No method throws (prepare*() and commit() included).
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
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/spinner.h>
#include <sensor_msgs/Image.h>
#include <diagnostic_updater/update_functions.h>
#include <std_srvs/Trigger.h>

#include "amcr/base/params.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/memory/memory_edits.h"
#include "amcr/memory/prototype_memory.h"
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
  /// and says why. Publishes the label table on success. Images are recognized with the previous memory
  /// until the swap.
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

  /// A rebuild made ready without the lock, from a copy of the state taken under it.
  struct PreparedSwap
  {
    std::uint64_t generation = 0;       ///< the memory generation it was built from
    std::string error;                  ///< why it could not be built (then there is nothing to swap)
    std::function<std::string()> swap;  ///< run under the lock; its error, empty on success; empty: no change
    std::size_t prototypes = 0;         ///< in the memory after the swap
  };
  /// ~load_prototypes and reconfigure() in their two steps (those methods run both in turn; a test puts
  /// another edit in between): the build, without the lock...
  PreparedSwap prepareLoad(const std::string& directory);
  PreparedSwap prepareReconfigure(const amcr::AMCRConfig& config, std::uint32_t level);
  /// ...and the swap under the lock, refused with kMemoryChanged when another swap landed since the
  /// build copied the state. Returns the error, empty on success (or when there was nothing to swap).
  std::string commit(PreparedSwap& prepared);
  /// Why a swap is refused when the memory changed while its rebuild was under way.
  static const char* const kMemoryChanged;

  /// An image that failed after process() returned (publishing): logged and counted as skipped.
  void reportSkipped(const sensor_msgs::Image& msg, const std::string& why);

  amcr::Params params() const;

private:
  /// The parameters and the memory of ~prototypes, logged when invalid; publishes the label table.
  void loadStartupState();
  /// The reconfigure server, /diagnostics and the services.
  void advertise(std::function<std::uint32_t()> overlay_subscribers);
  /// What a rebuild starts from: a copy of the state, taken under the lock.
  struct EditState
  {
    std::uint64_t generation = 0;
    amcr::Params params;
    std::shared_ptr<const amcr::PrototypeMemory> memory;
    amcr::MemoryEdits edits;  ///< the directory and this session's edits of its memory
    cv_bridge::CvImageConstPtr last_image;
  };
  EditState editState() const;  // takes the lock

  /// The one reset path (lock held): `replacement` (a new filter, fresh by construction) takes the
  /// place of the current one, or the current one is reset; the input's time and the statistics'
  /// frame sequence start again. Returns the filter replaced (free it after the lock).
  std::unique_ptr<amcr::Recognizer> restart(std::unique_ptr<amcr::Recognizer> replacement = nullptr);
  /// PrototypeMemory::loadDirectory with its skipped files logged as warnings and its progress as info.
  static amcr::PrototypeMemory loadDirectory(const std::string& directory, const amcr::Params& params);
  /// The load's swap (lock held): `tables` takes the place of the memory (the same recognizer, so track
  /// ids go on counting) and keeps what it replaced; the session's edits are forgotten.
  std::string swapLoaded(const std::string& directory, amcr::FilterMemory& tables, double build_seconds);
  /// The reconfiguration's swap (lock held): `changed` and its filter `rebuilt` (null while no memory is
  /// loaded), which keeps the filter replaced.
  std::string swapReconfigured(const amcr::Params& changed, std::shared_ptr<const amcr::PrototypeMemory> memory,
                               std::unique_ptr<amcr::Recognizer>& rebuilt, const std::string& what);
  /// Swaps in an edited memory made ready as `tables` (lock held): extended (the filter goes on) or not
  /// (it restarts); `tables` keeps what it replaced; the version counts up and the table is published.
  void swapEditedMemory(amcr::FilterMemory& tables, bool extended);
  /// teach(): the reason of a refusal, empty on success (then `response` is filled). Copies the state
  /// under the lock, cuts the shape and builds the memory and the filter's indexes without it (images
  /// go on being recognized), and takes it again to swap them in (commit()).
  std::string teachShape(const amcr::TeachPrototype::Request& request, amcr::TeachPrototype::Response& response);
  /// removePrototype()'s work, likewise; the reason of a refusal, empty on success.
  std::string removeLabel(const std::string& label, amcr::RemovePrototype::Response& response);
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

  // One rebuild at a time (never the frame lock): a second waits for the first, then builds on what it
  // swapped in.
  std::mutex rebuild_mutex_;

  mutable std::mutex mutex_;  // everything below
  amcr::Params params_;
  std::shared_ptr<const amcr::PrototypeMemory> memory_;
  std::unique_ptr<amcr::Recognizer> recognizer_;  // null while no memory is loaded
  ros::Time last_stamp_;
  cv::Size last_size_;
  bool fresh_ = true;   // no image processed since restart()
  // The last image the core saw (~teach cuts from it). The pointer, not its cv::Mat: the Mat may
  // share the message's buffer, which the pointer keeps alive.
  cv_bridge::CvImageConstPtr last_image_;
  std::uint32_t table_version_ = 0;
  std::uint64_t generation_ = 0;  // counts the swaps of the memory or the parameters
  /// The directory of the memory, the prototypes taught in this session and not saved, and the labels
  /// removed from the directory's memory (the edits forgotten by ~load_prototypes).
  amcr::MemoryEdits edits_;

  // Last: their callbacks use everything above. The queue of the rebuilding calls outlives their servers.
  ros::CallbackQueue edit_queue_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<amcr::AMCRConfig>> reconfigure_server_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  double min_input_rate_ = 1.0, max_input_rate_ = 0.0;  // Hz; read by the frequency status
  std::unique_ptr<diagnostic_updater::FrequencyStatus> input_rate_;
  std::unique_ptr<diagnostic_updater::TimeStampStatus> input_delay_;
  std::unique_ptr<diagnostic_updater::CompositeDiagnosticTask> input_status_;
  ros::WallTimer diagnostics_timer_;
  ros::ServiceServer srv_reset_, srv_load_, srv_teach_, srv_remove_;
  std::unique_ptr<ros::AsyncSpinner> edit_spinner_;  // stopped first: no rebuild runs past the members
};
}  // namespace amcr_ros
