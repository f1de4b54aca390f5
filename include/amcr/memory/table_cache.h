// An on-disk cache of the prototype tables: building the radial
// scan table of one prototype takes tens of ms, reading it back a fraction
// of that. One file per image, named by its label and the hash of the image
// file's bytes; its header holds a key of everything the table depends on,
// and a checksum of the payload. A file whose magic, version, key, size or
// checksum does not match is never trusted: the table is built again and
// the file replaced, and the reason is reported. Files are written to a
// temporary name in the same directory and renamed, so a crash or a second
// process never leaves half a file under the real name.
//
// File layout (host byte order; the cache is local to a machine):
//   magic "AMCRTBL\0" (8 bytes), format version (u32), header size (u32),
//   key (u64), payload size (u64), payload checksum (u64),
//   payload: Prototype::toBytes() (or, for the proposal index, its k-d
//   tree: index_cache.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"

namespace amcr
{
/// Changes whenever the table code or the payload layout changes, so that
/// files of an older build are rebuilt, not read.
constexpr std::uint32_t kTableFormatVersion = 3;  // 2: the table stride; 3: grey templates (kind, scan image)

/// The directory MemoryParams::table_cache_dir names, "~/" expanded: "" (the
/// default) is $ROS_HOME/amcr/tables, or $HOME/.ros/amcr/tables when
/// ROS_HOME is not set (roslaunch's own default for ROS_HOME). Returns ""
/// when the cache is off: "none", or the default with neither variable set
/// (then `why_off`, when given, says so).
std::string tableCacheDirectory(const std::string& setting, std::string* why_off = nullptr);

/// The key of a table: the hash of the image file's bytes, the parameters
/// the table is built with (prototype_size, edge_threshold, blur_sigma,
/// table_stride), the
/// table's constants (direction bins, distance unit, "no edge" value),
/// kTableFormatVersion and the OpenCV version (whose resize, distance
/// transform and blur make the table).
std::uint64_t tableCacheKey(std::uint64_t image_hash, const MemoryParams& params);

/// How the tables of a memory were found (PrototypeMemory::cacheCounts()).
struct TableCacheCounts
{
  std::size_t read = 0;      ///< tables read from the cache
  std::size_t built = 0;     ///< tables built (no cache, no file, or a refused file)
  std::size_t written = 0;   ///< tables written to the cache
  std::size_t refused = 0;   ///< files refused: damaged, stale or of another format
};

class TableCache
{
public:
  /// The result of read(): the prototype, or null and why ("" when there
  /// was no file).
  struct Found
  {
    std::shared_ptr<const Prototype> prototype;
    std::string problem;
  };

  /// A cache in `directory` ("" = off), created when missing. When it
  /// cannot be created or written to, problem() says why; a directory that
  /// exists but cannot be written to is still read.
  explicit TableCache(const std::string& directory);

  bool readable() const { return readable_; }
  bool writable() const { return writable_; }
  const std::string& directory() const { return directory_; }
  /// Why the cache cannot be used or written to; "" when it can, or is off.
  const std::string& problem() const { return problem_; }

  /// The file of the image with `label` whose bytes hash to `image_hash`.
  std::string path(const std::string& label, std::uint64_t image_hash) const;

  /// The prototype in the file, when the file holds a table with `key`
  /// whose checksum matches, as `instance` of `label` ("" = the label).
  /// Safe to call from several threads.
  Found read(const std::string& label, std::uint64_t image_hash, std::uint64_t key,
             const std::string& instance = std::string()) const;

  /// Writes the prototype's file under a temporary name, then renames it;
  /// returns why it could not ("" when written). Safe to call from several
  /// threads and processes.
  std::string write(const std::string& label, std::uint64_t image_hash, std::uint64_t key,
                    const Prototype& prototype) const;

  /// The cache file layout for any payload (the proposal index's k-d tree
  /// uses it too, index_cache.h): the payload of file `name` of the cache
  /// directory when its header holds `key` and the checksum matches. Returns
  /// why the file was refused; "" with an empty payload when there is no
  /// file (or the cache is off). Safe to call from several threads.
  std::string readPayload(const std::string& name, std::uint64_t key, std::vector<std::uint8_t>& payload) const;

  /// Writes `payload` under `key` as file `name` (temporary name, then a
  /// rename); returns why it could not ("" when written, or the cache is
  /// not writable).
  std::string writePayload(const std::string& name, std::uint64_t key, const std::vector<std::uint8_t>& payload) const;

  /// A path in the cache directory, next to `name`, that no other thread or
  /// process uses (for a file a library must write or read by name).
  std::string temporaryPath(const std::string& name) const;

private:
  static std::string fileName(const std::string& label, std::uint64_t image_hash);
  std::string filePath(const std::string& name) const;

  std::string directory_;
  bool readable_ = false;
  bool writable_ = false;
  std::string problem_;
};
}  // namespace amcr
