// The memory of prototypes M_1..M_r (spec "The problem").
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
class PrototypeMemory
{
public:
  /// Receives one readable line for every file that was skipped.
  using WarningSink = std::function<void(const std::string&)>;

  PrototypeMemory() = default;

  /// Loads every image file of `directory`: loose files (label = file name
  /// without extension) and label directories (label = the directory's
  /// name, each file in it an instance of it; prototype_directory.h),
  /// sorted by label, then instance. Unreadable files, images with no
  /// shape, empty label directories and labels taken twice are skipped with
  /// a warning naming the file. The tables are built on
  /// parallelFor's threads (parallel_for.h), or read from the table cache
  /// params.table_cache_dir names (table_cache.h); a cache file that is
  /// refused, or a cache that cannot be used, is a warning too. The memory
  /// is the same whatever the thread count and whatever came from the
  /// cache. Throws MemoryError when the directory is missing, empty, or no
  /// prototype is left. The tables' stride is chosen for the number of
  /// files first (chooseTableStride): its reason goes to `progress` when
  /// compact tables (a stride above 1) were chosen, and to `warn` when the
  /// tables may exceed params.table_budget_mb. A load that
  /// takes more than a few seconds sends a
  /// progress line to `progress` every few seconds (files done, built, read
  /// from the cache; called from the loading threads, one at a time).
  static PrototypeMemory loadDirectory(const std::string& directory, const MemoryParams& params,
                                       const WarningSink& warn = WarningSink(),
                                       const WarningSink& progress = WarningSink());

  /// Adds one prototype from an image in memory, at params.table_stride, or
  /// with table_stride 0 at the stride of the memory (tableStride()). With no `instance`, a new
  /// label (MemoryError when the label is taken; the instance is the
  /// label); with one, an instance of `label`, new or not (MemoryError when
  /// the instance is taken). MemoryError too when the image holds no shape.
  void add(const std::string& label, const cv::Mat& image, const MemoryParams& params,
           const std::string& instance = std::string());

  /// Removes every prototype of `label` and returns how many there were (0
  /// for an unknown label: nothing changes). The prototypes after them move
  /// down: their indices change.
  std::size_t remove(const std::string& label);

  /// True when the first size() prototypes of `other` are this memory's own
  /// (the same objects, in the same order): `other` extends this one.
  bool isPrefixOf(const PrototypeMemory& other) const;

  std::size_t size() const { return prototypes_.size(); }
  bool empty() const { return prototypes_.empty(); }
  const Prototype& operator[](std::size_t i) const { return *prototypes_[i]; }

  /// Index of the first prototype of a label, or -1.
  int find(const std::string& label) const;
  /// Index of the prototype of an instance (Prototype::instance()), or -1.
  int findInstance(const std::string& instance) const;
  /// The prototypes of a label, in memory order (empty for an unknown label).
  std::vector<int> instancesOf(const std::string& label) const;
  /// The distinct labels, in memory order.
  const std::vector<std::string>& labels() const { return labels_; }

  /// Memory held by all lookup tables, bytes.
  std::size_t tableBytes() const;

  /// The stride loadDirectory() chose or was given (chooseTableStride), or
  /// that of the first add(); 0 for an empty memory built by the default constructor.
  int tableStride() const { return table_stride_; }

  /// How loadDirectory() found the tables (all zero for a memory built by add()).
  const TableCacheCounts& cacheCounts() const { return cache_counts_; }

private:
  /// Appends a prototype; MemoryError when its label is taken.
  void append(std::shared_ptr<const Prototype> prototype);

  std::vector<std::shared_ptr<const Prototype>> prototypes_;
  std::vector<std::string> labels_;
  TableCacheCounts cache_counts_;
  int table_stride_ = 0;
};
}  // namespace amcr
