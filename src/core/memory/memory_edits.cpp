#include "amcr/memory/memory_edits.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
constexpr std::size_t kMaxLabelLength = 64;  // characters: the label is a file name too
}  // namespace

std::string labelRefusal(const std::string& label)
{
  if (label.empty())
    return "the label is empty";
  if (label.size() > kMaxLabelLength)
    return "the label '" + label + "' is longer than " + std::to_string(kMaxLabelLength) + " characters";
  if (label.front() == '.')
    return "the label '" + label + "' starts with '.'";
  for (char c : label)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.')
      return "the label '" + label + "' has a character other than letters, digits, '_', '-' and '.'";
  return "";
}

void MemoryEdits::loaded(const std::string& directory)
{
  directory_ = directory;
  taught_.clear();
  removed_.clear();
}

void MemoryEdits::addTaught(const std::string& label, const cv::Mat& image)
{
  taught_.push_back({label, image.clone()});
}

void MemoryEdits::addRemoval(const std::string& label)
{
  taught_.erase(std::remove_if(taught_.begin(), taught_.end(), [&label](const Taught& t) { return t.label == label; }),
                taught_.end());
  removed_.push_back(label);
}

std::shared_ptr<const PrototypeMemory> MemoryEdits::rebuild(const MemoryParams& params, const DirectoryReader& read) const
{
  auto memory = std::make_shared<PrototypeMemory>();
  if (!directory_.empty())
    *memory = read(directory_, params);
  for (const std::string& label : removed_)
    memory->remove(label);
  for (const Taught& shape : taught_)
    memory->add(shape.label, shape.image, params);
  if (memory->empty())
    throw MemoryError("the rebuilt memory holds no prototype");
  return memory;
}

std::string MemoryEdits::teachRefusal(const PrototypeMemory* memory, const std::string& label, bool save,
                                      std::string& saved_path) const
{
  saved_path.clear();
  const std::string why = labelRefusal(label);
  if (!why.empty())
    return why;
  if (memory && memory->find(label) >= 0)
    return "the label '" + label + "' is taken (" + std::to_string(memory->instancesOf(label).size()) +
           " prototypes): remove it first or pick another";
  if (!save)
    return "";
  if (directory_.empty())
    return "nowhere to save: the memory was not loaded from a directory";
  const std::string path = (std::filesystem::path(directory_) / (label + ".png")).string();
  std::error_code error;
  if (std::filesystem::exists(path, error))
    return "'" + path + "' exists already: remove it or pick another label";
  saved_path = path;
  return "";
}

std::string MemoryEdits::removalRefusal(const PrototypeMemory* memory, const std::string& label)
{
  if (!memory || memory->find(label) < 0)
    return "no label '" + label + "' in the memory";
  if (memory->labels().size() == 1)
    return "'" + label + "' is the memory's only label: load another memory instead";
  return "";
}
}  // namespace amcr
