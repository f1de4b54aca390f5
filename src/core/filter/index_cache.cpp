#include "amcr/filter/index_cache.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include <opencv2/core/version.hpp>
#include <opencv2/flann.hpp>

#include "amcr/base/content_hash.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
namespace fs = std::filesystem;

namespace
{
/// Removes a temporary file when it goes out of scope.
struct TemporaryFile
{
  std::string path;
  ~TemporaryFile()
  {
    std::error_code ignored;
    fs::remove(path, ignored);
  }
};
}  // namespace

std::uint64_t indexCacheKey(const cv::Mat& descriptors, int leaf_size)
{
  ContentHash key;
  key.addText("amcr proposal index k-d tree").addValue(kTableFormatVersion).addText(CV_VERSION);
  key.addValue(static_cast<std::int32_t>(leaf_size));
  key.addValue(static_cast<std::int32_t>(descriptors.rows)).addValue(static_cast<std::int32_t>(descriptors.cols));
  key.addValue(static_cast<std::int32_t>(descriptors.type()));
  for (int r = 0; r < descriptors.rows; ++r)  // row by row: the Mat need not be continuous
    key.add(descriptors.ptr(r), descriptors.cols * descriptors.elemSize());
  return key.value();
}

std::string indexCacheName(std::uint64_t key)
{
  std::ostringstream name;
  name << "index-" << std::hex << std::setw(16) << std::setfill('0') << key << ".kdtree";
  return name.str();
}

// FLANN reads and writes its trees by file name only: the verified payload
// goes through a temporary file of the cache directory.
std::unique_ptr<cv::flann::Index> readIndexTree(const TableCache& cache, std::uint64_t key,
                                                const cv::Mat& descriptors, std::string& problem)
{
  const std::string name = indexCacheName(key);
  std::vector<std::uint8_t> payload;
  problem = cache.readPayload(name, key, payload);
  if (!problem.empty() || payload.empty() || !cache.writable())
    return nullptr;
  const TemporaryFile tree_file{cache.temporaryPath(name)};
  {
    errno = 0;
    std::ofstream out(tree_file.path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    out.close();
    if (!out)
    {
      problem = "cannot write '" + tree_file.path + "': " + (errno ? std::strerror(errno) : "an input/output error");
      return nullptr;
    }
  }
  auto tree = std::make_unique<cv::flann::Index>();
  try
  {
    if (tree->load(descriptors, tree_file.path))
      return tree;
    problem = "FLANN did not accept the tree";
  }
  catch (const std::exception& e)  // cv::Exception from FLANN's reader
  {
    problem = std::string("FLANN could not read the tree: ") + e.what();
  }
  return nullptr;
}

std::string writeIndexTree(const TableCache& cache, std::uint64_t key, const cv::flann::Index& tree)
{
  if (!cache.writable())
    return "";
  const std::string name = indexCacheName(key);
  const TemporaryFile tree_file{cache.temporaryPath(name)};
  std::vector<std::uint8_t> payload;
  try
  {
    tree.save(tree_file.path);
    std::error_code error;
    const std::uintmax_t size = fs::file_size(tree_file.path, error);
    std::ifstream in(tree_file.path, std::ios::binary);
    if (!error)
    {
      payload.resize(static_cast<std::size_t>(size));
      in.read(reinterpret_cast<char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    }
    if (error || !in || payload.empty())
      return "cannot read back FLANN's file '" + tree_file.path + "'";
  }
  catch (const std::exception& e)
  {
    return std::string("FLANN could not write the tree: ") + e.what();
  }
  return cache.writePayload(name, key, payload);
}
}  // namespace amcr
