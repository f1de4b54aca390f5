// One prototype image file made into a prototype, through the table cache
// when there is one (table_cache.h): what PrototypeMemory::loadDirectory
// does for each file, on several threads at once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
struct LoadedPrototype
{
  std::shared_ptr<const Prototype> prototype;  ///< null when the file was skipped
  bool from_cache = false;                     ///< read from the cache, not built
  bool written = false;                        ///< built and stored in the cache
  bool refused = false;                        ///< a cache file was there and refused
  std::vector<std::string> warnings;           ///< each naming the file and the reason
};

/// Reads the image file at `path` and gives the prototype `label` (as
/// `instance` of it, "" = the label): from
/// `cache` when it holds a sound table for these bytes and parameters,
/// otherwise built (and then stored in `cache`). An unreadable file or an
/// image with no shape leaves `prototype` null with a warning; a cache file
/// that is refused, or cannot be written, gives a warning and a built table.
/// Thread-safe; never throws for a bad file.
LoadedPrototype loadPrototypeFile(const std::string& path, const std::string& label, const MemoryParams& params,
                                  const TableCache& cache, const std::string& instance = std::string());
}  // namespace amcr
