// RecognizerRos's edits of the memory at runtime (recognizer_ros.h): ~teach,
// ~remove_prototype, and the rebuild of an edited memory when the tables must
// be built again (a reconfiguration).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <exception>
#include <filesystem>
#include <system_error>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "amcr/errors.h"
#include "amcr/region_shape.h"
#include "recognizer_ros.h"

namespace amcr_ros
{
namespace
{
/// Empty when `label` can name a prototype (and its file): letters, digits, '_', '-', '.'; not
/// starting with '.'; at most 64 characters. Otherwise why not.
std::string checkLabel(const std::string& label)
{
  if (label.empty())
    return "the label is empty";
  if (label.size() > 64)
    return "the label '" + label + "' is longer than 64 characters";
  if (label.front() == '.')
    return "the label '" + label + "' starts with '.'";
  for (char c : label)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
      return "the label '" + label + "' has a character other than letters, digits, '_', '-' and '.'";
  return "";
}

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
  // Under the lock: the checks, and what the cut needs.
  cv_bridge::CvImageConstPtr image;
  amcr::Params params;
  std::shared_ptr<const amcr::PrototypeMemory> base;
  std::string saved;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string why = checkLabel(request.label);
    if (!why.empty())
      return why;
    if (memory_ && memory_->find(request.label) >= 0)
      return "the label '" + request.label + "' is taken (" +
             std::to_string(memory_->instancesOf(request.label).size()) +
             " prototypes): remove it with ~remove_prototype or pick another";
    if (request.save)
    {
      if (memory_directory_.empty())
        return "nowhere to save: no prototype directory is loaded (set ~prototypes or call ~load_prototypes)";
      saved = (std::filesystem::path(memory_directory_) / (request.label + ".png")).string();
      std::error_code error;
      if (std::filesystem::exists(saved, error))
        return "'" + saved + "' exists already: remove it or pick another label";
    }
    if (!last_image_)
      return "no image received yet: there is nothing to cut the shape from";
    image = last_image_;
    params = params_;
    base = memory_;
  }

  // Without the lock (the new prototype's table takes a few hundred ms): the cut and the new memory.
  const amcr::CutShape cut = amcr::cutShape(image->image, requestedRegion(request), params);
  if (!cut.why.empty())
    return cut.why;
  auto memory = base ? std::make_shared<amcr::PrototypeMemory>(*base) : std::make_shared<amcr::PrototypeMemory>();
  memory->add(request.label, cut.silhouette, params);  // MemoryError when the cut holds no usable shape

  // Under the lock again: the swap, unless the memory changed meanwhile.
  const auto cut_done = std::chrono::steady_clock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  if (memory_ != base)
    return "the memory changed while the shape was cut (a load, a reconfiguration or another ~teach): call again";
  if (!saved.empty() && !cv::imwrite(saved, cut.silhouette))
    return "cannot write '" + saved + "'";
  try
  {
    swapEditedMemory(memory, true);
  }
  catch (...)
  {
    if (!saved.empty())
      std::filesystem::remove(saved);  // nothing changed: not on disk either
    throw;
  }
  if (saved.empty())
    taught_.push_back({request.label, cut.silhouette.clone()});
  response.prototype_id = static_cast<int>(memory->size()) - 1;
  response.saved_path = saved;
  const std::string where = saved.empty() ? "not saved" : "saved to " + saved;
  const auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  const auto end = std::chrono::steady_clock::now();
  ROS_INFO("taught '%s' from a %d x %d px cut of the last image (prototype %d, %s) in %.0f ms (%.0f ms of it "
           "with the filter held: the proposal index); label table version %u",
           request.label.c_str(), cut.bounds.width, cut.bounds.height, response.prototype_id, where.c_str(),
           ms(end - start), ms(end - cut_done), table_version_);
  return "";
}

amcr::RemovePrototype::Response RecognizerRos::removePrototype(const std::string& label)
{
  amcr::RemovePrototype::Response response;
  std::lock_guard<std::mutex> lock(mutex_);
  try
  {
    if (!memory_ || memory_->find(label) < 0)
      response.message = "no label '" + label + "' in the memory";
    else if (memory_->labels().size() == 1)
      response.message = "'" + label + "' is the memory's only label: load another memory instead";
    else
    {
      auto memory = std::make_shared<amcr::PrototypeMemory>(*memory_);
      response.num_removed = static_cast<int>(memory->remove(label));
      swapEditedMemory(memory, false);
      taught_.erase(std::remove_if(taught_.begin(), taught_.end(),
                                   [&label](const TaughtShape& t) { return t.label == label; }),
                    taught_.end());
      removed_labels_.push_back(label);
      ROS_INFO("removed '%s' (%d prototypes; files untouched): filter restarted, label table version %u",
               label.c_str(), response.num_removed, table_version_);
    }
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
  response.table_version = table_version_;
  return response;
}

std::uint32_t RecognizerRos::tableVersion() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return table_version_;
}

void RecognizerRos::swapEditedMemory(std::shared_ptr<const amcr::PrototypeMemory> memory, bool extended)
{
  if (!recognizer_)
    restart(std::make_unique<amcr::Recognizer>(params_, memory));  // the first prototype
  else if (extended)
    recognizer_->extendMemory(memory);  // the filter goes on
  else
  {
    recognizer_->setMemory(memory);  // the indices moved: the same recognizer, track ids go on counting
    restart();
  }
  memory_ = std::move(memory);
  ++table_version_;
  stats_.setPrototypes(memory_->size(), "");
  publishPrototypeTable();
}

std::shared_ptr<const amcr::PrototypeMemory> RecognizerRos::rebuildMemory(const amcr::Params& params) const
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  if (!memory_directory_.empty())
    *memory = loadDirectory(memory_directory_, params);
  for (const std::string& label : removed_labels_)
    memory->remove(label);
  for (const TaughtShape& shape : taught_)
    memory->add(shape.label, shape.silhouette, params);
  if (memory->empty())
    throw amcr::MemoryError("the rebuilt memory holds no prototype");
  return memory;
}
}  // namespace amcr_ros
