#include "amcr/prototype_memory.h"

#include <algorithm>
#include <exception>
#include <filesystem>

#include "amcr/errors.h"
#include "amcr/prototype_file.h"
#include "amcr/resource_bounds.h"

namespace amcr
{
namespace fs = std::filesystem;

namespace
{
/// The regular files of `directory`; an entry whose type cannot be read (a
/// symlink loop, a dangling link, no permission) is skipped with a warning.
std::vector<fs::path> listFiles(const std::string& directory, const PrototypeMemory::WarningSink& warn)
{
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw MemoryError("the prototype directory '" + directory + "' " +
                      (error ? "cannot be read: " + error.message() : std::string("is not a directory")));
  std::vector<fs::path> files;
  fs::directory_iterator it(directory, error);
  for (; !error && it != fs::directory_iterator(); it.increment(error))
  {
    std::error_code entry_error;
    const bool regular = it->is_regular_file(entry_error);
    if (entry_error && warn)
      warn("skipped '" + it->path().string() + "': " + entry_error.message());
    if (regular)
      files.push_back(it->path());
  }
  if (error)
    throw MemoryError("cannot list the prototype directory '" + directory + "': " + error.message());
  if (files.empty())
    throw MemoryError("the prototype directory '" + directory + "' holds no files");
  std::sort(files.begin(), files.end());
  return files;
}

/// MemoryError when `count` more prototypes at `prototype_size` could take
/// the tables past kMaxTableBytes.
void checkTableBound(std::size_t held, std::size_t count, int prototype_size)
{
  const std::int64_t each = maxTableBytesPerPrototype(prototype_size);
  const std::int64_t total = static_cast<std::int64_t>(held) + static_cast<std::int64_t>(count) * each;
  if (total > kMaxTableBytes)
    throw MemoryError("the prototype tables would need up to " + formatBytes(total) + " (" +
                      (held ? formatBytes(static_cast<std::int64_t>(held)) + " held and " : std::string()) +
                      std::to_string(count) + " x " + formatBytes(each) + " at prototype_size " +
                      std::to_string(prototype_size) + "): above the bound of " + formatBytes(kMaxTableBytes));
}
}  // namespace

PrototypeMemory PrototypeMemory::loadDirectory(const std::string& directory, const Params& params,
                                               const WarningSink& warn)
{
  params.validate();
  const std::vector<fs::path> files = listFiles(directory, warn);
  checkTableBound(0, files.size(), params.prototype_size);

  std::string cache_off;
  const TableCache cache(tableCacheDirectory(params.table_cache_dir, &cache_off));
  if (warn && !cache_off.empty())
    warn(cache_off);
  if (warn && !cache.problem().empty())
    warn(cache.problem());

  // Each file into its own slot, on OpenCV's threads; warnings and errors
  // are taken in file order afterwards, so the memory and what is reported
  // do not depend on the thread count.
  std::vector<LoadedPrototype> loaded(files.size());
  std::vector<std::exception_ptr> failed(files.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(files.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i)
    {
      try
      {
        loaded[i] = loadPrototypeFile(files[i].string(), files[i].stem().string(), params, cache);
      }
      catch (...)  // not a bad file (bad_alloc, a cv::Exception): rethrown on this thread below
      {
        failed[i] = std::current_exception();
      }
    }
  });

  PrototypeMemory memory;
  for (std::size_t i = 0; i < files.size(); ++i)
  {
    if (failed[i])
      std::rethrow_exception(failed[i]);
    for (const std::string& w : loaded[i].warnings)
      if (warn)
        warn(w);
    if (!loaded[i].prototype)
      continue;
    try
    {
      memory.append(std::move(loaded[i].prototype));
    }
    catch (const MemoryError& e)  // a label taken by another extension
    {
      if (warn)
        warn("skipped '" + files[i].string() + "': " + e.what());
      continue;
    }
    TableCacheCounts& counts = memory.cache_counts_;
    counts.read += loaded[i].from_cache ? 1 : 0;
    counts.built += loaded[i].from_cache ? 0 : 1;
    counts.written += loaded[i].written ? 1 : 0;
    counts.refused += loaded[i].refused ? 1 : 0;
  }
  if (memory.empty())
    throw MemoryError("no usable prototype in '" + directory + "' (" + std::to_string(files.size()) +
                      " files, none a silhouette with edges)");
  return memory;
}

void PrototypeMemory::add(const std::string& label, const cv::Mat& image, const Params& params)
{
  if (find(label) >= 0)
    throw MemoryError("prototype label '" + label + "' is already in the memory");
  checkTableBound(tableBytes(), 1, params.prototype_size);
  append(std::make_shared<const Prototype>(label, image, params.prototype_size, params.edge_threshold,
                                           params.blur_sigma));
}

void PrototypeMemory::append(std::shared_ptr<const Prototype> prototype)
{
  if (find(prototype->label()) >= 0)
    throw MemoryError("prototype label '" + prototype->label() + "' is already in the memory");
  prototypes_.push_back(std::move(prototype));
}

int PrototypeMemory::find(const std::string& label) const
{
  for (std::size_t i = 0; i < prototypes_.size(); ++i)
    if (prototypes_[i]->label() == label)
      return static_cast<int>(i);
  return -1;
}

std::size_t PrototypeMemory::tableBytes() const
{
  std::size_t bytes = 0;
  for (const auto& p : prototypes_)
    bytes += p->tableBytes();
  return bytes;
}
}  // namespace amcr
