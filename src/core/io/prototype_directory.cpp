#include "amcr/io/prototype_directory.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "amcr/base/errors.h"

namespace amcr
{
namespace fs = std::filesystem;

namespace
{
struct Entries
{
  std::vector<fs::path> files;
  std::vector<fs::path> directories;
};

/// The regular files and directories of `directory`, each sorted; an entry
/// whose type cannot be read is skipped with a warning. `what` names the
/// directory in errors.
Entries listEntries(const fs::path& directory, const std::string& what,
                    const std::function<void(const std::string&)>& warn)
{
  std::error_code error;
  Entries entries;
  fs::directory_iterator it(directory, error);
  for (; !error && it != fs::directory_iterator(); it.increment(error))
  {
    std::error_code entry_error;
    const fs::file_status status = it->status(entry_error);
    if (entry_error || !fs::exists(status))
    {
      if (warn)
        warn("skipped '" + it->path().string() + "': " +
             (entry_error ? entry_error.message() : std::string("a link to nothing")));
      continue;
    }
    if (fs::is_regular_file(status))
      entries.files.push_back(it->path());
    else if (fs::is_directory(status))
      entries.directories.push_back(it->path());
    else if (warn)
      warn("skipped '" + it->path().string() + "': neither a file nor a directory");
  }
  if (error)
    throw MemoryError("cannot list " + what + " '" + directory.string() + "': " + error.message());
  std::sort(entries.files.begin(), entries.files.end());
  std::sort(entries.directories.begin(), entries.directories.end());
  return entries;
}
}  // namespace

std::vector<PrototypeSource> listPrototypeDirectory(const std::string& directory,
                                                    const std::function<void(const std::string&)>& warn)
{
  std::error_code error;
  if (!fs::is_directory(directory, error))
    throw MemoryError("the prototype directory '" + directory + "' " +
                      (error ? "cannot be read: " + error.message() : std::string("is not a directory")));
  const Entries top = listEntries(directory, "the prototype directory", warn);

  std::vector<PrototypeSource> sources;
  std::set<std::string> labels;
  for (const fs::path& sub : top.directories)
  {
    const std::string label = sub.filename().string();
    const Entries inside = listEntries(sub, "the label directory", warn);
    for (const fs::path& nested : inside.directories)
      if (warn)
        warn("skipped '" + nested.string() + "': a directory inside the label directory '" + label +
             "' (only one level of label directories is read)");
    if (inside.files.empty())
    {
      if (warn)
        warn("skipped the label directory '" + sub.string() + "': it holds no files");
      continue;
    }
    labels.insert(label);
    for (const fs::path& file : inside.files)
      sources.push_back({file.string(), label, label + "/" + file.filename().string()});
  }
  for (const fs::path& file : top.files)
  {
    const std::string label = file.stem().string();
    if (!labels.insert(label).second)
    {
      if (warn)
        warn("skipped '" + file.string() + "': the label '" + label + "' is taken by " +
             (fs::is_directory(fs::path(directory) / label) ? "the label directory '" + label + "'"
                                                            : std::string("another file of that name")));
      continue;
    }
    sources.push_back({file.string(), label, file.filename().string()});
  }
  if (sources.empty())
    throw MemoryError("the prototype directory '" + directory + "' holds no files (loose or in label directories)");
  std::stable_sort(sources.begin(), sources.end(), [](const PrototypeSource& a, const PrototypeSource& b) {
    return a.label != b.label ? a.label < b.label : a.instance < b.instance;
  });
  return sources;
}
}  // namespace amcr
