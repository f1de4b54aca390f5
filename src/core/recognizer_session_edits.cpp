// RecognizerSession's edits of the memory at runtime (recognizer_session.h): a
// teach and a removal, each checked (MemoryEdits), built without the frame
// lock and swapped in by commit() (recognizer_session.cpp).
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "amcr/base/parallel_for.h"
#include "amcr/memory/region_shape.h"
#include "amcr/recognizer_session.h"

namespace amcr
{
RecognizerSession::Taught RecognizerSession::teach(const std::string& label, const std::vector<cv::Point2f>& region,
                                                   bool save)
{
  Taught answer;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const SingleThreadScope beside_the_images;  // at this thread's priority, off the images' workers
    answer.error = teachShape(label, region, save, answer);
  }
  catch (const std::exception& e)
  {
    answer.error = std::string("teaching failed: ") + e.what();
  }
  answer.table_version = tableVersion();
  if (!answer.error.empty())
  {
    answer.prototype_id = -1;
    answer.saved_path.clear();
  }
  return answer;
}

std::string RecognizerSession::teachShape(const std::string& label, const std::vector<cv::Point2f>& region, bool save,
                                          Taught& answer)
{
  const auto start = std::chrono::steady_clock::now();
  // The checks on a copy of the state (commit() refuses the swap when it changed meanwhile).
  const EditState state = editState();
  std::string saved;
  std::string why = state.edits.teachRefusal(state.memory.get(), label, save, saved);
  if (!why.empty())
    return why;
  if (state.last_image.image.empty())
    return "no image received yet: there is nothing to cut the shape from";

  // Without the lock (images go on being recognized): the cut, the new memory and the filter's indexes.
  const CutShape cut = cutShape(state.last_image.image, region, state.params);
  if (!cut.why.empty())
    return cut.why;
  auto memory = state.memory ? std::make_shared<PrototypeMemory>(*state.memory) : std::make_shared<PrototypeMemory>();
  memory->add(label, cut.prototypeImage(), state.params);  // MemoryError when the cut holds no usable shape
  FilterMemory tables(state.params, std::move(memory));

  // Under the lock: the swap, unless the memory changed meanwhile.
  const auto built = std::chrono::steady_clock::now();
  PreparedSwap prepared;
  prepared.generation = state.generation;
  prepared.swap = [&] {
    if (!saved.empty() && !cv::imwrite(saved, cut.prototypeImage()))
      return "cannot write '" + saved + "'";
    try
    {
      swapEditedMemory(tables, true);
    }
    catch (...)
    {
      if (!saved.empty())
        std::filesystem::remove(saved);  // nothing changed: not on disk either
      throw;
    }
    if (saved.empty())
      edits_.addTaught(label, cut.prototypeImage());
    answer.prototype_id = static_cast<int>(memory_->size()) - 1;
    return std::string();
  };
  why = commit(prepared);
  if (!why.empty())
    return why;
  answer.saved_path = saved;
  const std::string where = saved.empty() ? "not saved" : "saved to " + saved;
  const auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  const auto end = std::chrono::steady_clock::now();
  char line[1024];
  std::snprintf(line, sizeof line,
                "taught '%s' from a %d x %d px cut of the last image (prototype %d, %s) in %.0f ms (%.0f ms of it "
                "for the swap); label table version %u",
                label.c_str(), cut.bounds.width, cut.bounds.height, answer.prototype_id, where.c_str(),
                ms(end - start), ms(end - built), tableVersion());
  inform(line);
  return "";
}

RecognizerSession::Removed RecognizerSession::remove(const std::string& label)
{
  Removed answer;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const SingleThreadScope beside_the_images;
    answer.error = removeLabel(label, answer);
  }
  catch (const std::exception& e)
  {
    answer.error = std::string("removing failed: ") + e.what();
  }
  if (!answer.error.empty())
    answer.removed = 0;
  answer.table_version = tableVersion();
  return answer;
}

std::string RecognizerSession::removeLabel(const std::string& label, Removed& answer)
{
  const EditState state = editState();
  const std::string refused = MemoryEdits::removalRefusal(state.memory.get(), label);
  if (!refused.empty())
    return refused;
  // Without the lock: the smaller memory and the filter's indexes.
  auto memory = std::make_shared<PrototypeMemory>(*state.memory);
  const int removed = static_cast<int>(memory->remove(label));
  FilterMemory tables(state.params, std::move(memory));
  PreparedSwap prepared;
  prepared.generation = state.generation;
  prepared.swap = [&] {
    swapEditedMemory(tables, false);
    edits_.addRemoval(label);
    inform("removed '" + label + "' (" + std::to_string(removed) +
           " prototypes; files untouched): filter restarted, label table version " + std::to_string(table_version_));
    return std::string();
  };
  const std::string why = commit(prepared);
  if (why.empty())
    answer.removed = removed;
  return why;
}

void RecognizerSession::swapEditedMemory(FilterMemory& tables, bool extended)
{
  installMemory(tables, extended);
  tableChanged();
}

void RecognizerSession::installMemory(FilterMemory& tables, bool extended)
{
  std::shared_ptr<const PrototypeMemory> memory = tables.memory();
  if (!recognizer_)
    restart(std::make_unique<Recognizer>(std::move(tables)));  // the first prototype
  else if (extended)
    tables = recognizer_->extendMemory(std::move(tables));  // the filter goes on
  else
  {
    tables = recognizer_->setMemory(std::move(tables));  // the indices moved: the same recognizer, track ids go on
    restart();
  }
  memory_ = std::move(memory);
}
}  // namespace amcr
