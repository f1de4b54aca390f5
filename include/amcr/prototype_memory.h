// The memory of prototypes M_1..M_r (spec "The problem").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/params.h"
#include "amcr/prototype.h"
#include "amcr/table_cache.h"

namespace amcr
{
class PrototypeMemory
{
public:
  /// Receives one readable line for every file that was skipped.
  using WarningSink = std::function<void(const std::string&)>;

  PrototypeMemory() = default;

  /// Loads every image file of `directory` (sorted by name; label = file name
  /// without extension). Unreadable files and images with no shape are
  /// skipped with a warning naming the file. The tables are built on
  /// OpenCV's threads (cv::parallel_for_), or read from the table cache
  /// params.table_cache_dir names (table_cache.h); a cache file that is
  /// refused, or a cache that cannot be used, is a warning too. The memory
  /// is the same whatever the thread count and whatever came from the
  /// cache. Throws MemoryError when the directory is missing, empty, or no
  /// prototype is left.
  static PrototypeMemory loadDirectory(const std::string& directory, const Params& params,
                                       const WarningSink& warn = WarningSink());

  /// Adds one prototype from an image in memory. Throws MemoryError when it
  /// holds no shape, or when the label is already taken.
  void add(const std::string& label, const cv::Mat& image, const Params& params);

  std::size_t size() const { return prototypes_.size(); }
  bool empty() const { return prototypes_.empty(); }
  const Prototype& operator[](std::size_t i) const { return *prototypes_[i]; }

  /// Index of a label, or -1.
  int find(const std::string& label) const;

  /// Memory held by all lookup tables, bytes.
  std::size_t tableBytes() const;

  /// How loadDirectory() found the tables (all zero for a memory built by add()).
  const TableCacheCounts& cacheCounts() const { return cache_counts_; }

private:
  /// Appends a prototype; MemoryError when its label is taken.
  void append(std::shared_ptr<const Prototype> prototype);

  std::vector<std::shared_ptr<const Prototype>> prototypes_;
  TableCacheCounts cache_counts_;
};
}  // namespace amcr
