// A running recognizer whose memory and parameters are edited while images
// stream in, without ROS: the parameters, the prototype memory and the
// amcr::Recognizer, with loads, teaching, removal and reconfiguration. The
// nodelet (src/ros/recognizer_ros.h) serves one through ROS; a program or a
// test drives it directly (test/test_recognizer_session.cpp).
//
//   amcr::RecognizerSession session(amcr::loadParams("config/amcr.yaml"));
//   session.load("prototypes/");
//   for (const cv::Mat& frame : frames)
//     amcr::RecognizedFrame out = session.recognize(frame);
//   session.teach("flag", amcr::rectangleRegion(10, 10, 80, 60), false);
//
// Images are recognized under one lock (the frame lock). A rebuild (a load, a
// teach, a removal, a reconfiguration) never builds under it: it copies what
// it needs under the lock, builds the new memory and filter without it while
// images go on being recognized with the old filter, and takes the lock again
// only to swap them in (commit()). The swap is refused when another one landed
// meanwhile (the generation, which counts the swaps, changed): nothing changes
// and the caller is told to try again (kMemoryChanged). Rebuilds run one at a
// time (the rebuild lock): a second waits for the first, then builds on what
// it swapped in.
//
// Every restart of the filter goes one way (reset(), a load, a removal, a
// reconfiguration, the input going back in time); a teach does not restart it
// (the taught prototype joins the running filter). No public method throws:
// errors come back as text.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/extraction/recognition_result.h"
#include "amcr/memory/memory_edits.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"

namespace amcr
{
/// The memory's label table as a host shows it.
struct LabelTable
{
  std::shared_ptr<const PrototypeMemory> memory;  ///< null while none is loaded
  std::string directory;                          ///< where it was loaded from; empty: none
  std::uint32_t version = 0;                      ///< counts the changes of the table
};

/// What a session tells its host, to log, publish or count; each may be empty. They are called from the
/// session's calls, some with its frame lock held (so that they come in the order of the swaps): they
/// must not call the session.
struct SessionHooks
{
  std::function<void(const std::string&)> warning;  ///< a file a load skipped, a prototype an index leaves out
  std::function<void(const std::string&)> info;     ///< a load's progress, what a swap did
  std::function<void()> restarted;                  ///< the filter starts again from the next image
  std::function<void(const LabelTable&)> table_changed;  ///< a load, a teach, a removal, a rebuild reordering it
};

/// An image for RecognizerSession::recognize.
struct FrameInput
{
  FrameInput() = default;
  /// An image that owns its pixels, no overlay, no restart; implicit, so that recognize(frame) reads well.
  FrameInput(cv::Mat frame) : image(std::move(frame)) {}

  cv::Mat image;  ///< any type Recognizer::step takes
  /// Keeps the pixels of `image` alive while the session keeps it as the last image (teach() cuts from
  /// it), when `image` only views them (a message's buffer); null when `image` owns them.
  std::shared_ptr<const void> pixels_owner;
  bool draw_overlay = false;
  /// The input went back in time (a looped bag): the filter starts again first, unless it is fresh (no
  /// image recognized since it started).
  bool restart_unless_fresh = false;
};

/// What RecognizerSession::recognize gave.
struct RecognizedFrame
{
  bool recognized = false;  ///< false: skipped, `error` says why (empty: no memory loaded yet)
  std::string error;
  RecognitionResult result;                       ///< the core's result: objects best score first, its time_ms
  std::shared_ptr<const PrototypeMemory> memory;  ///< the memory the objects refer to
  std::uint32_t table_version = 0;                ///< the label table's version the objects refer to
  /// The parameters the image was recognized with (shared: an image copies a pointer, not the Params).
  std::shared_ptr<const Params> params;
  bool restarted = false;        ///< the first image since the filter (re)started
  bool input_restart = false;    ///< restarted first, as FrameInput::restart_unless_fresh asked
  cv::Mat overlay;               ///< bgr8, only when asked for
  std::string overlay_error;     ///< why the overlay was not drawn (the recognitions stand)
};

class RecognizerSession
{
public:
  /// Why a swap is refused when another one landed while its rebuild was under way.
  static constexpr const char* kMemoryChanged =
      "the memory changed during the rebuild (another load, ~teach, ~remove_prototype or reconfiguration "
      "landed first); nothing changed: try again";

  /// Starts with `params` and no memory: images are skipped until a load or a teach succeeds (a load
  /// with invalid parameters is refused saying why).
  explicit RecognizerSession(Params params, SessionHooks hooks = {});
  ~RecognizerSession();
  RecognizerSession(const RecognizerSession&) = delete;
  RecognizerSession& operator=(const RecognizerSession&) = delete;

  /// Recognizes one image with the filter in use (under the frame lock, also while a rebuild is under
  /// way) and keeps it as the last image, also when no memory is loaded; draws the overlay when asked.
  RecognizedFrame recognize(const FrameInput& input);
  /// The filter starts again from the next image. Returns what was done.
  std::string reset();

  Params params() const;
  LabelTable labelTable() const;
  std::uint32_t tableVersion() const;

  /// What load(), teach() and remove() answer; `error` empty on success. On failure nothing changed.
  struct Loaded
  {
    std::string error;
    std::size_t prototypes = 0;  ///< in the memory loaded
  };
  struct Taught
  {
    std::string error;
    int prototype_id = -1;       ///< the new prototype's index in the memory
    std::string saved_path;      ///< where it was saved; empty: not saved
    std::uint32_t table_version = 0;  ///< the label table's version after the call
  };
  struct Removed
  {
    std::string error;
    int removed = 0;             ///< prototypes of the label removed
    std::uint32_t table_version = 0;
  };
  /// A reconfiguration, made from the parameters in effect when its rebuild starts: the parameters to use
  /// and what changed, in words for the log (empty: nothing; then nothing is swapped). The function may
  /// throw (ParameterError naming a value): the reconfiguration is refused with its text.
  struct Reconfiguration
  {
    Params params;
    std::string changes;
  };
  using ReconfigurationFrom = std::function<Reconfiguration(const Params& in_effect)>;

  // The rebuilds, each under the rebuild lock and built on the calling thread alone (SingleThreadScope: the
  // workers stay with the images).
  /// Loads the prototypes of `directory` and swaps them in (the filter restarts; the session's edits are
  /// forgotten); the previous memory stays on failure.
  Loaded load(const std::string& directory);
  /// Cuts the shape inside `region` (input px) of the last image (cutShape) and adds it as a prototype of
  /// the new `label` to the running filter (no restart); with `save`, writes it to <directory>/<label>.png.
  Taught teach(const std::string& label, const std::vector<cv::Point2f>& region, bool save);
  /// Removes every prototype of `label` (the filter restarts; the files stay).
  Removed remove(const std::string& label);
  /// Rebuilds the filter with the parameters `make` gives, and the tables too when `rebuild_tables` or a
  /// parameter that builds them changed (tablesDiffer; the session's edits are kept). Returns the error
  /// (empty on success); on an error the parameters in effect stay.
  std::string reconfigure(const ReconfigurationFrom& make, bool rebuild_tables);

  /// A rebuild made ready without the frame lock, from a copy of the state taken under it.
  struct PreparedSwap
  {
    std::uint64_t generation = 0;       ///< the generation it was built from
    std::string error;                  ///< why it could not be built (then there is nothing to swap)
    std::function<std::string()> swap;  ///< run under the frame lock; its error, empty on success; empty: no change
    std::size_t prototypes = 0;         ///< in the memory after the swap
  };
  /// load() and reconfigure() in their two steps (those run both in turn, a test puts another edit in
  /// between; neither takes the rebuild lock): the build...
  PreparedSwap prepareLoad(const std::string& directory);
  PreparedSwap prepareReconfigure(const ReconfigurationFrom& make, bool rebuild_tables);
  /// ...and the swap under the frame lock, refused with kMemoryChanged when another swap landed since the
  /// build copied the state. Returns the error, empty on success (or when there was nothing to swap).
  std::string commit(PreparedSwap& prepared);

private:
  /// The last image recognize() was given, with the owner of its pixels.
  struct LastImage
  {
    cv::Mat image;
    std::shared_ptr<const void> pixels_owner;
  };
  /// What a rebuild starts from: a copy of the state, taken under the frame lock.
  struct EditState
  {
    std::uint64_t generation = 0;
    Params params;
    std::shared_ptr<const PrototypeMemory> memory;
    MemoryEdits edits;
    LastImage last_image;  // its pixels kept alive while a teach cuts from them
  };
  EditState editState() const;

  /// The one restart path (frame lock held): `replacement` (a new filter, fresh by construction) takes the
  /// place of the current one, or the current one is reset. Returns the filter replaced (free it after
  /// the lock).
  std::unique_ptr<Recognizer> restart(std::unique_ptr<Recognizer> replacement = nullptr);
  /// PrototypeMemory::loadDirectory with its skipped files and progress told to the hooks.
  PrototypeMemory loadDirectory(const std::string& directory, const MemoryParams& params) const;
  /// The swaps (frame lock held); each takes what it swaps in and keeps in it what it replaced.
  std::string swapLoaded(const std::string& directory, FilterMemory& tables, double build_seconds);
  std::string swapReconfigured(const Reconfiguration& change, std::shared_ptr<const PrototypeMemory> memory,
                               std::unique_ptr<Recognizer>& rebuilt);
  /// A memory made ready as `tables` takes the place of the one in use: extended (the filter goes on) or
  /// not (it restarts; a first memory gets its recognizer). The label table's news is the caller's.
  void installMemory(FilterMemory& tables, bool extended);
  /// An edited memory made ready as `tables` (installMemory), then the news of the label table.
  void swapEditedMemory(FilterMemory& tables, bool extended);
  /// teach() and remove() within the rebuild lock: the reason of a refusal, empty on success.
  std::string teachShape(const std::string& label, const std::vector<cv::Point2f>& region, bool save, Taught& answer);
  std::string removeLabel(const std::string& label, Removed& answer);
  /// Tell the hooks; the last two with the frame lock held.
  void warn(const std::string& text) const;
  void inform(const std::string& text) const;
  /// The label table changed: its version counts up and the hooks are told.
  void tableChanged();
  /// What the filter's proposal index left out, as warnings.
  void indexWarnings();
  /// Notes a change of the image size (frame lock held).
  void followSize(const cv::Size& size);

  const SessionHooks hooks_;
  // One rebuild at a time (never the frame lock): a second waits for the first, then builds on what it
  // swapped in.
  std::mutex rebuild_mutex_;

  mutable std::mutex frame_mutex_;  // everything below
  std::shared_ptr<const Params> params_;  // replaced whole by a reconfiguration, never null
  std::shared_ptr<const PrototypeMemory> memory_;
  std::unique_ptr<Recognizer> recognizer_;  // null while no memory is loaded
  bool fresh_ = true;                       // no image recognized since restart()
  LastImage last_image_;                    // what teach() cuts from
  cv::Size last_size_;                      // of the last image recognized
  std::uint32_t table_version_ = 0;
  std::uint64_t generation_ = 0;  // counts the swaps of the memory or the parameters
  /// The directory of the memory, the prototypes taught and not saved, and the labels removed from the
  /// directory's memory (forgotten by a load).
  MemoryEdits edits_;
};
}  // namespace amcr
