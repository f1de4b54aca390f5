// Helpers of the libFuzzer targets: reading fields from the fuzzer's bytes, and a file of a
// process-wide temporary directory that each input is written to (for the APIs that take a path).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>

namespace amcr_fuzz
{
/// Reads fields from the front of the input; past its end every field reads as 0.
class ByteReader
{
public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::uint8_t byte() { return position_ < size_ ? data_[position_++] : 0; }

  /// Little-endian unsigned 16 / 32-bit.
  std::uint32_t u16() { return byte() | (static_cast<std::uint32_t>(byte()) << 8); }
  std::uint32_t u32() { return u16() | (u16() << 16); }

  /// Up to `count` bytes as a string.
  std::string text(std::size_t count)
  {
    std::string s;
    while (count-- > 0 && position_ < size_)
      s.push_back(static_cast<char>(data_[position_++]));
    return s;
  }

  const std::uint8_t* rest() const { return data_ + position_; }
  std::size_t restSize() const { return size_ - position_; }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t position_ = 0;
};

/// One directory per fuzzing process (removed at exit); `file(name)` is a path inside it.
class ScratchDirectory
{
public:
  ScratchDirectory()
  {
    std::string pattern = (std::filesystem::temp_directory_path() / "amcr_fuzz_XXXXXX").string();
    if (!mkdtemp(&pattern[0]))
      std::abort();
    path_ = pattern;
  }
  ~ScratchDirectory()
  {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

  /// Writes the bytes to `name` in the directory (replacing it) and returns its path.
  std::string write(const std::string& name, const std::uint8_t* data, std::size_t size) const
  {
    const std::string file = (path_ / name).string();
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return file;
  }

private:
  std::filesystem::path path_;
};

/// Quiet OpenCV, one thread (reproducible runs), and an image size bound that keeps a decoder
/// from allocating gigabytes on a forged header (OpenCV reads the variable at its first decode).
inline void setUpOpenCv()
{
  setenv("OPENCV_IO_MAX_IMAGE_PIXELS", "1048576", 0);
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  cv::setNumThreads(0);
}
}  // namespace amcr_fuzz
