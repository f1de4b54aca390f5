// RecognizerSession's rebuilds of the whole memory (recognizer_session.h): a
// load and a reconfiguration, each built without the frame lock from a copy of
// the state and swapped in under it by commit().
#include <chrono>
#include <cstdio>
#include <exception>
#include <utility>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "amcr/base/parallel_for.h"
#include "amcr/recognizer_session.h"

namespace amcr
{
namespace
{
/// The same prototypes in the same order (what the label table shows).
bool sameLabelTable(const PrototypeMemory& a, const PrototypeMemory& b)
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

PrototypeMemory RecognizerSession::loadDirectory(const std::string& directory, const MemoryParams& params) const
{
  return PrototypeMemory::loadDirectory(
      directory, params, [this](const std::string& w) { warn("prototypes: " + w); },
      [this](const std::string& line) { inform(line); });
}

RecognizerSession::Loaded RecognizerSession::load(const std::string& directory)
{
  Loaded answer;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const SingleThreadScope beside_the_images;  // at this thread's priority, off the images' workers
    PreparedSwap prepared = prepareLoad(directory);
    answer.error = commit(prepared);
    answer.prototypes = answer.error.empty() ? prepared.prototypes : 0;
    returnFreedMemory();  // commit() has destroyed the swap, and the replaced memory with it
  }
  catch (const std::exception& e)
  {
    answer.error = std::string("loading failed: ") + e.what();
    answer.prototypes = 0;
  }
  return answer;
}

RecognizerSession::PreparedSwap RecognizerSession::prepareLoad(const std::string& directory)
{
  PreparedSwap prepared;
  try
  {
    const EditState state = editState();
    prepared.generation = state.generation;
    const auto start = std::chrono::steady_clock::now();
    const auto memory = std::make_shared<const PrototypeMemory>(loadDirectory(directory, state.params));
    // A copy of a lambda shares its captures: the swap leaves the replaced memory here.
    const auto tables = std::make_shared<FilterMemory>(state.params, memory);
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

std::string RecognizerSession::swapLoaded(const std::string& directory, FilterMemory& tables, double build_seconds)
{
  const std::shared_ptr<const PrototypeMemory> memory = tables.memory();
  const char* meanwhile = memory_ ? ", images recognized meanwhile with the previous memory" : "";
  installMemory(tables, false);  // the same recognizer when there is one: track ids go on counting
  edits_.loaded(directory);
  indexWarnings();
  const TableCacheCounts& counts = memory->cacheCounts();
  char line[512];
  std::snprintf(line, sizeof line, "loaded %zu prototypes from '%s' in %.1f s%s (tables: %zu read from the cache, "
                "%zu built, %zu stored)", memory->size(), directory.c_str(), build_seconds, meanwhile, counts.read,
                counts.built, counts.written);
  inform(line);
  tableChanged();
  return "";
}

std::string RecognizerSession::reconfigure(const ReconfigurationFrom& make, bool rebuild_tables)
{
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const SingleThreadScope beside_the_images;
    PreparedSwap prepared = prepareReconfigure(make, rebuild_tables);
    const std::string error = commit(prepared);
    returnFreedMemory();
    return error;
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
}

RecognizerSession::PreparedSwap RecognizerSession::prepareReconfigure(const ReconfigurationFrom& make,
                                                                      bool rebuild_tables)
{
  PreparedSwap prepared;
  try
  {
    const EditState state = editState();
    prepared.generation = state.generation;
    Reconfiguration change = make(state.params);  // refuses a value out of range, naming it
    change.params.validate();
    if (change.changes.empty())
      return prepared;  // nothing new: nothing to swap
    std::shared_ptr<const PrototypeMemory> memory = state.memory;
    if (memory && (rebuild_tables || tablesDiffer(change.params, state.params)))
      memory = state.edits.rebuild(change.params, [this](const std::string& directory, const MemoryParams& params) {
        return loadDirectory(directory, params);
      });
    auto rebuilt = std::make_shared<std::unique_ptr<Recognizer>>();
    if (memory)
      *rebuilt = std::make_unique<Recognizer>(change.params, memory);  // refuses priors naming no prototype
    prepared.prototypes = memory ? memory->size() : 0;
    prepared.swap = [this, change, memory, rebuilt] { return swapReconfigured(change, memory, *rebuilt); };
  }
  catch (const std::exception& e)
  {
    prepared.error = e.what();
  }
  return prepared;
}

std::string RecognizerSession::swapReconfigured(const Reconfiguration& change,
                                                std::shared_ptr<const PrototypeMemory> memory,
                                                std::unique_ptr<Recognizer>& rebuilt)
{
  const bool tables_rebuilt = memory != memory_;
  // A prototype taught and saved now comes from the directory, in its sorted place: a new table.
  const bool table_changed = tables_rebuilt && !sameLabelTable(*memory, *memory_);
  params_ = std::make_shared<const Params>(change.params);
  memory_ = std::move(memory);
  rebuilt = restart(std::move(rebuilt));  // null only while no memory is loaded: then there is no filter either
  if (table_changed)
    tableChanged();
  indexWarnings();
  const char* what = !memory_ ? "no prototypes loaded yet"
                     : tables_rebuilt ? "prototype tables and filter rebuilt" : "filter rebuilt";
  inform("reconfigured (" + change.changes + "): " + what);
  return "";
}
}  // namespace amcr
