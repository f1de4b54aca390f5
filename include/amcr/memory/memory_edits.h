// The edits made to a running memory, without ROS: prototypes taught and not
// saved, labels removed (their files untouched), on top of the directory the
// memory was loaded from. A rebuild with other table parameters loads the
// directory again and applies them, so they survive it; loading a directory
// forgets them. Also the checks a teach or a removal must pass on the memory
// in use. amcr::RecognizerSession (amcr/recognizer_session.h) keeps one under
// its frame lock and copies it for a rebuild; the class itself takes no lock.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"

namespace amcr
{
/// Why `label` cannot name a prototype and its file, empty when it can:
/// letters, digits, '_', '-' and '.', not starting with '.', at most 64
/// characters.
std::string labelRefusal(const std::string& label);

class MemoryEdits
{
public:
  /// A prototype taught in this session and not saved.
  struct Taught
  {
    std::string label;
    cv::Mat image;  ///< as PrototypeMemory::add takes it (a silhouette, or a template with alpha)
  };
  /// Reads a prototype directory (PrototypeMemory::loadDirectory, with the
  /// caller's warnings): the same reader for a load and a rebuild.
  using DirectoryReader = std::function<PrototypeMemory(const std::string& directory, const MemoryParams& params)>;

  /// The directory the memory was loaded from; empty: none (a memory taught from scratch).
  const std::string& directory() const { return directory_; }
  const std::vector<Taught>& taught() const { return taught_; }
  const std::vector<std::string>& removedLabels() const { return removed_; }

  /// A memory of `directory` is in use now: the edits of the previous one are forgotten.
  void loaded(const std::string& directory);
  /// `label` was taught from `image` and not saved (the image is copied).
  void addTaught(const std::string& label, const cv::Mat& image);
  /// Every prototype of `label` was removed; one taught in this session is forgotten.
  void addRemoval(const std::string& label);

  /// The memory of directory() (none when it is empty) read by `read` with
  /// `params`, the labels removed, the prototypes taught added (in the order
  /// taught). Throws MemoryError when no prototype is left, or from `read`.
  std::shared_ptr<const PrototypeMemory> rebuild(const MemoryParams& params, const DirectoryReader& read) const;

  /// Why teaching `label` into `memory` (null: none loaded yet) is refused,
  /// empty when it may go ahead. With `save`, the file it is to be written to
  /// (<directory>/<label>.png) goes to `saved_path`: refused without a
  /// directory or when that file exists.
  std::string teachRefusal(const PrototypeMemory* memory, const std::string& label, bool save,
                           std::string& saved_path) const;
  /// Why removing `label` from `memory` (null: none loaded yet) is refused:
  /// an unknown label, or the memory's only one. Empty when it may go ahead.
  static std::string removalRefusal(const PrototypeMemory* memory, const std::string& label);

private:
  std::string directory_;
  std::vector<Taught> taught_;
  std::vector<std::string> removed_;
};
}  // namespace amcr
