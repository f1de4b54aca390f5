#include "amcr/prototype_memory.h"

#include <algorithm>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "amcr/errors.h"

namespace amcr
{
namespace fs = std::filesystem;

PrototypeMemory PrototypeMemory::loadDirectory(const std::string& directory, const Params& params,
                                               const WarningSink& warn)
{
  params.validate();
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw MemoryError("the prototype directory '" + directory + "' does not exist or is not a directory");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(directory, error))
    if (entry.is_regular_file())
      files.push_back(entry.path());
  if (error)
    throw MemoryError("cannot list the prototype directory '" + directory + "': " + error.message());
  if (files.empty())
    throw MemoryError("the prototype directory '" + directory + "' holds no files");
  std::sort(files.begin(), files.end());

  PrototypeMemory memory;
  for (const auto& file : files)
  {
    cv::Mat image;
    try
    {
      image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception&)
    {
      image.release();
    }
    if (image.empty())
    {
      if (warn)
        warn("skipped '" + file.string() + "': not a readable image");
      continue;
    }
    try
    {
      memory.add(file.stem().string(), image, params);
    }
    catch (const MemoryError& e)
    {
      if (warn)
        warn("skipped '" + file.string() + "': " + e.what());
    }
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
  prototypes_.push_back(std::make_shared<const Prototype>(label, image, params.prototype_size, params.edge_threshold,
                                                      params.blur_sigma));
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
