#include "amcr/prototype_memory.h"

#include <algorithm>
#include <filesystem>

#include "amcr/errors.h"
#include "amcr/image_file.h"
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

  PrototypeMemory memory;
  for (const auto& file : files)
  {
    try
    {
      memory.add(file.stem().string(), readImageFile(file.string()), params);
    }
    catch (const InputError& e)  // the file
    {
      if (warn)
        warn("skipped '" + file.string() + "': " + e.what());
    }
    catch (const MemoryError& e)  // the image
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
  checkTableBound(tableBytes(), 1, params.prototype_size);
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
