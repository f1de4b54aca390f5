#include "amcr/memory/prototype_memory.h"

#include <algorithm>
#include <exception>
#include <atomic>
#include <chrono>
#include <mutex>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/io/prototype_directory.h"
#include "amcr/memory/prototype_file.h"
#include "amcr/memory/table_stride_choice.h"

namespace amcr
{
namespace
{
constexpr double kProgressSeconds = 5.0;  // a progress line at most this often while tables load

/// Progress lines of a long load: "prototype tables: 400 of 1330 files
/// (380 built, 20 from the cache), 12 s", at most one per kProgressSeconds,
/// from whichever loading thread passes the mark.
class LoadProgress
{
public:
  LoadProgress(std::size_t total, const PrototypeMemory::WarningSink& sink)
    : total_(total), sink_(sink), start_(std::chrono::steady_clock::now()), last_(start_)
  {
  }

  void done(bool from_cache)
  {
    ++done_;
    if (from_cache)
      ++cached_;
    if (!sink_)
      return;
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(mutex_);
    if (std::chrono::duration<double>(now - last_).count() < kProgressSeconds)
      return;
    last_ = now;
    const std::size_t done = done_, cached = cached_;
    sink_("prototype tables: " + std::to_string(done) + " of " + std::to_string(total_) + " files (" +
          std::to_string(done - cached) + " built, " + std::to_string(cached) + " from the cache), " +
          std::to_string(static_cast<int>(std::chrono::duration<double>(now - start_).count())) + " s");
  }

private:
  const std::size_t total_;
  const PrototypeMemory::WarningSink& sink_;
  const std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_;
  std::atomic<std::size_t> done_{0};
  std::atomic<std::size_t> cached_{0};
  std::mutex mutex_;
};

/// MemoryError when `count` more prototypes at `prototype_size` and
/// `table_stride` could take the tables past kMaxTableBytes.
void checkTableBound(std::size_t held, std::size_t count, int prototype_size, int table_stride)
{
  const std::int64_t each = maxTableBytesPerPrototype(prototype_size, table_stride);
  const std::int64_t total = static_cast<std::int64_t>(held) + static_cast<std::int64_t>(count) * each;
  if (total > kMaxTableBytes)
    throw MemoryError("the prototype tables would need up to " + formatBytes(total) + " (" +
                      (held ? formatBytes(static_cast<std::int64_t>(held)) + " held and " : std::string()) +
                      std::to_string(count) + " x " + formatBytes(each) + " at prototype_size " +
                      std::to_string(prototype_size) + ", table_stride " + std::to_string(table_stride) + "): above the bound of " + formatBytes(kMaxTableBytes));
}
}  // namespace

PrototypeMemory PrototypeMemory::loadDirectory(const std::string& directory, const MemoryParams& params,
                                               const WarningSink& warn, const WarningSink& progress)
{
  params.validate();
  const std::vector<PrototypeSource> files = listPrototypeDirectory(directory, warn);
  const TableStrideChoice stride = chooseTableStride(files.size(), params);
  if (stride.over_budget && warn)
    warn(stride.reason);
  else if (stride.stride > 1 && params.table_stride == 0 && progress)
    progress(stride.reason);  // compact tables chosen: say why (exact ones go without a word)
  MemoryParams table_params = params;  // what the tables are built with, the stride resolved
  table_params.table_stride = stride.stride;
  checkTableBound(0, files.size(), params.prototype_size, table_params.table_stride);

  std::string cache_off;
  const TableCache cache(tableCacheDirectory(params.table_cache_dir, &cache_off));
  if (warn && !cache_off.empty())
    warn(cache_off);
  if (warn && !cache.problem().empty())
    warn(cache.problem());

  // Each file into its own slot, on OpenCV's threads (parallel_for.h);
  // warnings and errors are taken in file order afterwards, so the memory
  // and what is reported do not depend on the thread count.
  std::vector<LoadedPrototype> loaded(files.size());
  std::vector<std::exception_ptr> failed(files.size());
  LoadProgress load_progress(files.size(), progress);
  parallelFor(static_cast<int>(files.size()), resolveThreads(0), [&](int i) {
    try
    {
      loaded[i] = loadPrototypeFile(files[i].path, files[i].label, table_params, cache, files[i].instance);
      load_progress.done(loaded[i].from_cache);
    }
    catch (...)  // not a bad file (bad_alloc, a cv::Exception): rethrown on this thread below
    {
      failed[i] = std::current_exception();
    }
  });

  PrototypeMemory memory;
  memory.table_stride_ = stride.stride;
  for (std::size_t i = 0; i < files.size(); ++i)
  {
    if (failed[i])
      std::rethrow_exception(failed[i]);
    for (const std::string& w : loaded[i].warnings)
      if (warn)
        warn(w);
    if (!loaded[i].prototype)
      continue;
    // Each instance (a file relative to the directory) comes once from
    // listPrototypeDirectory, which has already skipped labels taken twice.
    memory.append(std::move(loaded[i].prototype));
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

void PrototypeMemory::add(const std::string& label, const cv::Mat& image, const MemoryParams& params,
                          const std::string& instance)
{
  if (instance.empty() && find(label) >= 0)
    throw MemoryError("prototype label '" + label + "' is already in the memory");
  if (table_stride_ == 0)  // the first prototype of a memory built one by one
    table_stride_ = params.table_stride > 0 ? params.table_stride : chooseTableStride(1, params).stride;
  const int stride = params.table_stride > 0 ? params.table_stride : table_stride_;
  checkTableBound(tableBytes(), 1, params.prototype_size, stride);
  append(std::make_shared<const Prototype>(label, image, params.prototype_size, params.edge_threshold,
                                           params.blur_sigma, stride, instance, params.edge_full_strength,
                                           params.keep_polarity));
}

void PrototypeMemory::append(std::shared_ptr<const Prototype> prototype)
{
  if (findInstance(prototype->instance()) >= 0)
    throw MemoryError("prototype instance '" + prototype->instance() + "' is already in the memory");
  if (find(prototype->label()) < 0)
    labels_.push_back(prototype->label());
  prototypes_.push_back(std::move(prototype));
}

std::size_t PrototypeMemory::remove(const std::string& label)
{
  const std::size_t before = prototypes_.size();
  prototypes_.erase(std::remove_if(prototypes_.begin(), prototypes_.end(),
                                   [&label](const std::shared_ptr<const Prototype>& p) { return p->label() == label; }),
                    prototypes_.end());
  labels_.erase(std::remove(labels_.begin(), labels_.end(), label), labels_.end());
  return before - prototypes_.size();
}

bool PrototypeMemory::isPrefixOf(const PrototypeMemory& other) const
{
  if (other.prototypes_.size() < prototypes_.size())
    return false;
  for (std::size_t i = 0; i < prototypes_.size(); ++i)
    if (other.prototypes_[i] != prototypes_[i])
      return false;
  return true;
}

int PrototypeMemory::find(const std::string& label) const
{
  for (std::size_t i = 0; i < prototypes_.size(); ++i)
    if (prototypes_[i]->label() == label)
      return static_cast<int>(i);
  return -1;
}

int PrototypeMemory::findInstance(const std::string& instance) const
{
  for (std::size_t i = 0; i < prototypes_.size(); ++i)
    if (prototypes_[i]->instance() == instance)
      return static_cast<int>(i);
  return -1;
}

std::vector<int> PrototypeMemory::instancesOf(const std::string& label) const
{
  std::vector<int> found;
  for (std::size_t i = 0; i < prototypes_.size(); ++i)
    if (prototypes_[i]->label() == label)
      found.push_back(static_cast<int>(i));
  return found;
}

std::size_t PrototypeMemory::tableBytes() const
{
  std::size_t bytes = 0;
  for (const auto& p : prototypes_)
    bytes += p->tableBytes();
  return bytes;
}
}  // namespace amcr
