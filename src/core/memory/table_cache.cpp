#include "amcr/memory/table_cache.h"

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include <unistd.h>

#include <opencv2/core/version.hpp>

#include "amcr/base/content_hash.h"
#include "amcr/base/errors.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace fs = std::filesystem;

namespace
{
constexpr char kMagic[8] = {'A', 'M', 'C', 'R', 'T', 'B', 'L', '\0'};

struct Header
{
  char magic[8];
  std::uint32_t version;
  std::uint32_t header_bytes;
  std::uint64_t key;
  std::uint64_t payload_bytes;
  std::uint64_t checksum;
};
static_assert(sizeof(Header) == 40, "the header is written as it lies in memory");

std::string hex(std::uint64_t value)
{
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << value;
  return out.str();
}

std::string systemReason() { return errno ? std::strerror(errno) : "an input/output error"; }

/// The whole file, or why it could not be read.
std::string readFile(const std::string& path, std::vector<std::uint8_t>& bytes)
{
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path, error);
  if (error)
    return error.message();
  if (size > static_cast<std::uintmax_t>(kMaxTableBytes))
    return "the file has " + std::to_string(size) + " bytes, more than any cache file holds";
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return systemReason();
  bytes.resize(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    return "it changed while it was read";
  return "";
}

/// Why a file's header does not fit `key` and its payload, or "".
std::string checkHeader(const std::vector<std::uint8_t>& bytes, std::uint64_t key)
{
  Header h;
  if (bytes.size() < sizeof h)
    return "truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the " + std::to_string(sizeof h) +
           "-byte header";
  std::memcpy(&h, bytes.data(), sizeof h);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0)
    return "not a table file (wrong magic)";
  if (h.version != kTableFormatVersion || h.header_bytes != sizeof h)
    return "format version " + std::to_string(h.version) + ", this build reads version " +
           std::to_string(kTableFormatVersion);
  if (h.key != key)
    return "stale: made for other table parameters, another image or another OpenCV (key " + hex(h.key) +
           ", expected " + hex(key) + ")";
  const std::uint64_t held = bytes.size() - sizeof h;
  if (h.payload_bytes != held)
    return (held < h.payload_bytes ? "truncated: " : "too long: ") + std::to_string(held) +
           " payload bytes where the header gives " + std::to_string(h.payload_bytes);
  if (hashBytes(bytes.data() + sizeof h, held) != h.checksum)
    return "damaged: the payload's checksum does not match";
  return "";
}

/// A name no other thread or process writes to at the same time.
std::string temporaryName(const std::string& final_name)
{
  static std::atomic<unsigned long> counter{0};
  return final_name + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}
}  // namespace

std::string tableCacheDirectory(const std::string& setting, std::string* why_off)
{
  if (setting == "none")
    return "";
  const char* home = std::getenv("HOME");
  if (setting.compare(0, 2, "~/") == 0)
  {
    if (home && *home)
      return (fs::path(home) / setting.substr(2)).string();
    if (why_off)
      *why_off = "table_cache_dir '" + setting + "' starts with '~/' but HOME is not set";
    return "";
  }
  if (!setting.empty())
    return setting;
  const char* ros_home = std::getenv("ROS_HOME");
  if (ros_home && *ros_home)
    return (fs::path(ros_home) / "amcr" / "tables").string();
  if (home && *home)
    return (fs::path(home) / ".ros" / "amcr" / "tables").string();
  if (why_off)
    *why_off = "no table cache: neither ROS_HOME nor HOME is set (set table_cache_dir)";
  return "";
}

std::uint64_t tableCacheKey(std::uint64_t image_hash, const MemoryParams& params)
{
  ContentHash key;
  key.addText("amcr prototype table").addValue(kTableFormatVersion).addText(CV_VERSION);
  key.addValue(image_hash);
  key.addValue(static_cast<std::int32_t>(params.prototype_size));
  key.addValue(params.edge_threshold).addValue(params.edge_full_strength).addValue(params.blur_sigma);
  key.addValue(static_cast<std::int32_t>(params.keep_polarity ? 1 : 0));
  key.addValue(static_cast<std::int32_t>(params.table_stride));
  key.addValue(static_cast<std::int32_t>(kDirectionBins)).addValue(Prototype::kDistanceUnit);
  key.addValue(Prototype::kNoEdge);
  return key.value();
}

TableCache::TableCache(const std::string& directory) : directory_(directory)
{
  if (directory_.empty())
    return;
  std::error_code error;
  fs::create_directories(directory_, error);
  if (error || !fs::is_directory(directory_, error))
  {
    problem_ = "the table cache '" + directory_ + "' cannot be used (" +
               (error ? error.message() : std::string("not a directory")) + "): every table is built";
    return;
  }
  readable_ = true;
  // Try a write now, so that an unwritable directory is reported once, not once per table.
  const std::string probe = temporaryName((fs::path(directory_) / "probe").string());
  errno = 0;
  std::ofstream out(probe, std::ios::binary);
  writable_ = static_cast<bool>(out);
  if (!writable_)
    problem_ = "the table cache '" + directory_ + "' cannot be written to (" + systemReason() +
               "): tables are read from it but not stored";
  out.close();
  fs::remove(probe, error);
}

std::string TableCache::fileName(const std::string& label, std::uint64_t image_hash)
{
  return label + "-" + hex(image_hash) + ".table";
}

std::string TableCache::path(const std::string& label, std::uint64_t image_hash) const
{
  return filePath(fileName(label, image_hash));
}

std::string TableCache::filePath(const std::string& name) const { return (fs::path(directory_) / name).string(); }

std::string TableCache::temporaryPath(const std::string& name) const { return temporaryName(filePath(name)); }

std::string TableCache::readPayload(const std::string& name, std::uint64_t key, std::vector<std::uint8_t>& payload) const
{
  payload.clear();
  if (!readable_)
    return "";
  const std::string file = filePath(name);
  std::error_code error;
  if (!fs::exists(file, error))
    return "";
  std::vector<std::uint8_t> bytes;
  std::string problem = readFile(file, bytes);
  if (problem.empty())
    problem = checkHeader(bytes, key);
  if (problem.empty())
    payload.assign(bytes.begin() + sizeof(Header), bytes.end());
  return problem;
}

std::string TableCache::writePayload(const std::string& name, std::uint64_t key,
                                     const std::vector<std::uint8_t>& payload) const
{
  if (!writable_)
    return "";
  Header h;
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kTableFormatVersion;
  h.header_bytes = sizeof h;
  h.key = key;
  h.payload_bytes = payload.size();
  h.checksum = hashBytes(payload.data(), payload.size());

  const std::string file = filePath(name);
  const std::string temporary = temporaryName(file);
  errno = 0;
  std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
  if (out)
  {
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    out.close();
  }
  std::error_code error;
  if (!out)
  {
    const std::string reason = systemReason();
    fs::remove(temporary, error);
    return "cannot write '" + temporary + "': " + reason;
  }
  fs::rename(temporary, file, error);  // atomic on POSIX: readers see the old file or the new one
  if (error)
  {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    return "cannot rename '" + temporary + "' to '" + file + "': " + error.message();
  }
  return "";
}

TableCache::Found TableCache::read(const std::string& label, std::uint64_t image_hash, std::uint64_t key,
                                   const std::string& instance) const
{
  Found found;
  std::vector<std::uint8_t> payload;
  found.problem = readPayload(fileName(label, image_hash), key, payload);
  if (!found.problem.empty() || payload.empty())
    return found;
  try
  {
    found.prototype = Prototype::fromBytes(label, payload.data(), payload.size(), instance);
  }
  catch (const MemoryError& e)
  {
    found.problem = std::string("inconsistent payload: ") + e.what();
  }
  return found;
}

std::string TableCache::write(const std::string& label, std::uint64_t image_hash, std::uint64_t key,
                              const Prototype& prototype) const
{
  if (!writable_)
    return "";
  return writePayload(fileName(label, image_hash), key, prototype.toBytes());
}
}  // namespace amcr
