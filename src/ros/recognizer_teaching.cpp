// RecognizerRos's edits of the memory at runtime (recognizer_ros.h): ~teach
// and ~remove_prototype, each checked (amcr::MemoryEdits, ROS-free), built
// without the frame lock and swapped in by commit() (recognizer_reload.cpp).
#include <chrono>
#include <exception>
#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/memory/region_shape.h"
#include "recognizer_ros.h"

namespace amcr_ros
{
namespace
{
/// The request's region: its polygon, or its rectangle when the polygon has no points.
std::vector<cv::Point2f> requestedRegion(const amcr::TeachPrototype::Request& request)
{
  std::vector<cv::Point2f> region;
  for (const auto& p : request.region.points)
    region.emplace_back(p.x, p.y);
  if (region.empty())
    region = amcr::rectangleRegion(request.rectangle.x_offset, request.rectangle.y_offset, request.rectangle.width,
                                   request.rectangle.height);
  return region;
}
}  // namespace

amcr::TeachPrototype::Response RecognizerRos::teach(const amcr::TeachPrototype::Request& request)
{
  amcr::TeachPrototype::Response response;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const amcr::SingleThreadScope beside_the_images;  // at this thread's priority, off the images' workers
    response.message = teachShape(request, response);
  }
  catch (const std::exception& e)
  {
    response.message = std::string("teaching failed: ") + e.what();
  }
  response.success = response.message.empty();
  response.table_version = tableVersion();
  if (!response.success)
  {
    response.prototype_id = -1;
    response.saved_path.clear();
    ROS_ERROR("~teach '%s' refused, nothing changed: %s", request.label.c_str(), response.message.c_str());
  }
  return response;
}

std::string RecognizerRos::teachShape(const amcr::TeachPrototype::Request& request,
                                      amcr::TeachPrototype::Response& response)
{
  const auto start = std::chrono::steady_clock::now();
  // The checks on a copy of the state (commit() refuses the swap when it changed meanwhile).
  const EditState state = editState();
  std::string saved;
  std::string why = state.edits.teachRefusal(state.memory.get(), request.label, request.save, saved);
  if (!why.empty())
    return why;
  if (!state.last_image)
    return "no image received yet: there is nothing to cut the shape from";

  // Without the lock (images go on being recognized): the cut, the new memory and the filter's indexes.
  const amcr::CutShape cut = amcr::cutShape(state.last_image->image, requestedRegion(request), state.params);
  if (!cut.why.empty())
    return cut.why;
  auto memory = state.memory ? std::make_shared<amcr::PrototypeMemory>(*state.memory)
                             : std::make_shared<amcr::PrototypeMemory>();
  memory->add(request.label, cut.prototypeImage(), state.params);  // MemoryError when the cut holds no usable shape
  amcr::FilterMemory tables(state.params, std::move(memory));

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
      edits_.addTaught(request.label, cut.prototypeImage());
    response.prototype_id = static_cast<int>(memory_->size()) - 1;
    return std::string();
  };
  why = commit(prepared);
  if (!why.empty())
    return why;
  response.saved_path = saved;
  const std::string where = saved.empty() ? "not saved" : "saved to " + saved;
  const auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  const auto end = std::chrono::steady_clock::now();
  ROS_INFO("taught '%s' from a %d x %d px cut of the last image (prototype %d, %s) in %.0f ms (%.0f ms of it "
           "for the swap); label table version %u",
           request.label.c_str(), cut.bounds.width, cut.bounds.height, response.prototype_id, where.c_str(),
           ms(end - start), ms(end - built), tableVersion());
  return "";
}

amcr::RemovePrototype::Response RecognizerRos::removePrototype(const std::string& label)
{
  amcr::RemovePrototype::Response response;
  try
  {
    std::lock_guard<std::mutex> rebuilding(rebuild_mutex_);
    const amcr::SingleThreadScope beside_the_images;
    response.message = removeLabel(label, response);
  }
  catch (const std::exception& e)
  {
    response.message = std::string("removing failed: ") + e.what();
  }
  response.success = response.message.empty();
  if (!response.success)
  {
    response.num_removed = 0;
    ROS_ERROR("~remove_prototype '%s' refused, nothing changed: %s", label.c_str(), response.message.c_str());
  }
  response.table_version = tableVersion();
  return response;
}

std::string RecognizerRos::removeLabel(const std::string& label, amcr::RemovePrototype::Response& response)
{
  const EditState state = editState();
  const std::string refused = amcr::MemoryEdits::removalRefusal(state.memory.get(), label);
  if (!refused.empty())
    return refused;
  // Without the lock: the smaller memory and the filter's indexes.
  auto memory = std::make_shared<amcr::PrototypeMemory>(*state.memory);
  const int removed = static_cast<int>(memory->remove(label));
  amcr::FilterMemory tables(state.params, std::move(memory));
  PreparedSwap prepared;
  prepared.generation = state.generation;
  prepared.swap = [&] {
    swapEditedMemory(tables, false);
    edits_.addRemoval(label);
    ROS_INFO("removed '%s' (%d prototypes; files untouched): filter restarted, label table version %u", label.c_str(),
             removed, table_version_);
    return std::string();
  };
  const std::string why = commit(prepared);
  if (why.empty())
    response.num_removed = removed;
  return why;
}

std::uint32_t RecognizerRos::tableVersion() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return table_version_;
}

void RecognizerRos::swapEditedMemory(amcr::FilterMemory& tables, bool extended)
{
  std::shared_ptr<const amcr::PrototypeMemory> memory = tables.memory();
  if (!recognizer_)
    restart(std::make_unique<amcr::Recognizer>(std::move(tables)));  // the first prototype
  else if (extended)
    tables = recognizer_->extendMemory(std::move(tables));  // the filter goes on
  else
  {
    tables = recognizer_->setMemory(std::move(tables));  // the indices moved: the same recognizer, track ids go on
    restart();
  }
  memory_ = std::move(memory);
  ++table_version_;
  stats_.setPrototypes(memory_->size(), "");
  publishPrototypeTable();
}
}  // namespace amcr_ros
