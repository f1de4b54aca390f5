// RecognizerRos's rebuilds (recognizer_ros.h): ~load_prototypes and the
// reconfiguration, each built without the frame lock from a copy of the state
// and swapped in under it by commit(), which refuses the swap when the memory
// generation changed since the copy.
#include <chrono>
#include <exception>
#include <utility>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "recognizer_ros.h"
#include "reconfigure.h"

namespace amcr_ros
{
namespace
{
/// The same prototypes in the same order (what the label table shows).
bool sameLabelTable(const amcr::PrototypeMemory& a, const amcr::PrototypeMemory& b)
{
  if (a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].instance() != b[i].instance() || a[i].label() != b[i].label())
      return false;
  return true;
}

/// Gives the pages a replaced memory freed back to the system. glibc keeps
/// freed memory in the allocating thread's arena, and a rebuild allocates on
/// its own thread: without this, the process would keep the high-water mark
/// of the largest memory it ever held (tens to hundreds of MB).
void returnFreedMemory()
{
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

double secondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

const char* const RecognizerRos::kMemoryChanged =
    "the memory changed during the rebuild (another load, ~teach, ~remove_prototype or reconfiguration "
    "landed first); nothing changed: try again";

RecognizerRos::EditState RecognizerRos::editState() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return {generation_, params_, memory_, edits_, last_image_};
}

std::string RecognizerRos::commit(PreparedSwap& prepared)
{
  if (!prepared.error.empty())
    return prepared.error;
  // Destroyed after the lock is released, with whatever the swap replaced and left in its captures.
  const std::function<std::string()> swap = std::move(prepared.swap);
  prepared.swap = nullptr;
  if (!swap)
    return "";
  try
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (generation_ != prepared.generation)
      return kMemoryChanged;
    const std::string error = swap();
    if (error.empty())
      ++generation_;
    return error;
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
}

amcr::PrototypeMemory RecognizerRos::loadDirectory(const std::string& directory, const amcr::Params& params)
{
  return amcr::PrototypeMemory::loadDirectory(
      directory, params, [](const std::string& w) { ROS_WARN("prototypes: %s", w.c_str()); },
      [](const std::string& line) { ROS_INFO("%s", line.c_str()); });
}

RecognizerRos::PreparedSwap RecognizerRos::prepareLoad(const std::string& directory)
{
  PreparedSwap prepared;
  try
  {
    const EditState state = editState();
    prepared.generation = state.generation;
    const auto start = std::chrono::steady_clock::now();
    const auto memory = std::make_shared<const amcr::PrototypeMemory>(loadDirectory(directory, state.params));
    // A copy of a lambda shares its captures: the swap leaves the replaced memory here.
    const auto tables = std::make_shared<amcr::FilterMemory>(state.params, memory);
    const double build_seconds = secondsSince(start);
    prepared.prototypes = memory->size();
    prepared.swap = [this, directory, tables, build_seconds] { return swapLoaded(directory, *tables, build_seconds); };
  }
  catch (const std::exception& e)
  {
    prepared.error = "cannot load prototypes from '" + directory + "': " + e.what();
  }
  return prepared;
}

std::string RecognizerRos::swapLoaded(const std::string& directory, amcr::FilterMemory& tables, double build_seconds)
{
  const std::shared_ptr<const amcr::PrototypeMemory> memory = tables.memory();
  const char* meanwhile = memory_ ? ", images recognized meanwhile with the previous memory" : "";
  if (recognizer_)
  {
    tables = recognizer_->setMemory(std::move(tables));  // the same recognizer: track ids go on counting
    restart();
  }
  else
    restart(std::make_unique<amcr::Recognizer>(std::move(tables)));
  memory_ = memory;
  edits_.loaded(directory);
  ++table_version_;
  for (const std::string& w : recognizer_->filter().indexWarnings())
    ROS_WARN("proposal index: %s", w.c_str());
  const amcr::TableCacheCounts& counts = memory->cacheCounts();
  ROS_INFO("loaded %zu prototypes from '%s' in %.1f s%s (tables: %zu read from the cache, %zu built, %zu stored)",
           memory->size(), directory.c_str(), build_seconds, meanwhile, counts.read, counts.built, counts.written);
  stats_.setPrototypes(memory->size(), "");
  publishPrototypeTable();
  return "";
}

amcr::LoadPrototypes::Response RecognizerRos::loadPrototypes(const std::string& directory)
{
  amcr::LoadPrototypes::Response response;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const amcr::SingleThreadScope beside_the_images;  // at this thread's priority, off the images' workers
    PreparedSwap prepared = prepareLoad(directory);
    response.message = commit(prepared);
    response.success = response.message.empty();
    response.num_prototypes = response.success ? static_cast<int>(prepared.prototypes) : 0;
    returnFreedMemory();  // commit() has destroyed the swap, and the replaced memory with it
  }
  catch (const std::exception& e)
  {
    response.message = std::string("loading failed: ") + e.what();
  }
  if (!response.success)
  {
    response.num_prototypes = 0;
    ROS_ERROR("%s (the previous memory stays in use)", response.message.c_str());
    std::lock_guard<std::mutex> lock(mutex_);
    if (!memory_)
      stats_.setPrototypes(0, response.message);
  }
  return response;
}

std::string RecognizerRos::reconfigure(amcr::AMCRConfig& config, std::uint32_t level)
{
  std::string error;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const amcr::SingleThreadScope beside_the_images;
    PreparedSwap prepared = prepareReconfigure(config, level);
    error = commit(prepared);
    returnFreedMemory();
  }
  catch (const std::exception& e)
  {
    error = e.what();
  }
  if (!error.empty())
    ROS_ERROR("reconfiguration refused, the previous parameters stay: %s", error.c_str());
  try
  {
    config = toConfig(params());  // what is in effect is what the server keeps and the clients see
  }
  catch (const std::exception& e)
  {
    ROS_ERROR("cannot show the parameters in effect: %s", e.what());
  }
  return error;
}

RecognizerRos::PreparedSwap RecognizerRos::prepareReconfigure(const amcr::AMCRConfig& config, std::uint32_t level)
{
  PreparedSwap prepared;
  try
  {
    const EditState state = editState();
    prepared.generation = state.generation;
    amcr::Params changed = fromConfig(config, state.params);  // refuses a value out of range, naming it
    changed.validate();
    const std::string what = describeChanges(state.params, changed);
    if (what.empty())
      return prepared;  // the initial call, or nothing new: nothing to swap
    std::shared_ptr<const amcr::PrototypeMemory> memory = state.memory;
    if (memory && ((level & kReconfigureTables) || amcr::tablesDiffer(changed, state.params)))
      memory = state.edits.rebuild(changed, &RecognizerRos::loadDirectory);
    auto rebuilt = std::make_shared<std::unique_ptr<amcr::Recognizer>>();
    if (memory)
      *rebuilt = std::make_unique<amcr::Recognizer>(changed, memory);  // refuses priors naming no prototype
    prepared.prototypes = memory ? memory->size() : 0;
    prepared.swap = [this, changed, memory, rebuilt, what] { return swapReconfigured(changed, memory, *rebuilt, what); };
  }
  catch (const std::exception& e)
  {
    prepared.error = e.what();
  }
  return prepared;
}

std::string RecognizerRos::swapReconfigured(const amcr::Params& changed,
                                            std::shared_ptr<const amcr::PrototypeMemory> memory,
                                            std::unique_ptr<amcr::Recognizer>& rebuilt, const std::string& what)
{
  const bool tables_rebuilt = memory != memory_;
  // A prototype taught and saved now comes from the directory, in its sorted place: a new table.
  const bool table_changed = tables_rebuilt && !sameLabelTable(*memory, *memory_);
  params_ = changed;
  memory_ = std::move(memory);
  rebuilt = restart(std::move(rebuilt));  // null only while no memory is loaded: then there is no filter either
  if (table_changed)
  {
    ++table_version_;
    publishPrototypeTable();
  }
  if (recognizer_)
    for (const std::string& w : recognizer_->filter().indexWarnings())
      ROS_WARN("proposal index: %s", w.c_str());
  ROS_INFO("reconfigured (%s): %s", what.c_str(),
           !memory_ ? "no prototypes loaded yet"
                    : tables_rebuilt ? "prototype tables and filter rebuilt" : "filter rebuilt");
  return "";
}

}  // namespace amcr_ros
