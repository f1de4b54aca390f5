// The layout of a prototype directory: which image files it
// holds and the label and instance of each. Two kinds of entry, side by side:
//   <dir>/star.png           a loose file: label "star", instance "star.png"
//   <dir>/bird/bird-3.png    a label directory: label "bird", instance
//                            "bird/bird-3.png" (every file in it is an
//                            instance of "bird")
// Only one level of sub-directories is read.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace amcr
{
/// One image file of a prototype directory.
struct PrototypeSource
{
  std::string path;      ///< the file
  std::string label;     ///< the sub-directory's name, or the loose file's name without extension
  std::string instance;  ///< the file relative to the directory ("bird/bird-3.png", "star.png")
};

/// The files of `directory`, loose files and label directories merged,
/// sorted by label, then instance. Each entry that cannot be used is
/// skipped with one line to `warn` naming it and why: an entry whose type
/// cannot be read (a symlink loop, a dangling link), a directory inside a
/// label directory, a label directory that holds no files, and a loose file
/// whose label is taken (by a label directory, or by a loose file of the
/// same name and another extension, which comes later by name). Throws
/// MemoryError when the directory is missing, cannot be listed, or holds
/// no file at all.
std::vector<PrototypeSource> listPrototypeDirectory(const std::string& directory,
                                                    const std::function<void(const std::string&)>& warn);
}  // namespace amcr
