// Bytes in and out of the table cache's payloads (table_cache.h), in the
// machine's byte order: a writer that appends fields, and a reader that
// checks every size against the bytes left, so that a faulty file becomes a
// MemoryError naming the field, never an out-of-bounds read.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/errors.h"

namespace amcr
{
class ByteWriter
{
public:
  template <typename T>
  void put(const T& value)
  {
    putBytes(&value, sizeof value);
  }
  void putBytes(const void* data, std::size_t size)
  {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
  }
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

private:
  std::vector<std::uint8_t> bytes_;
};

class ByteReader
{
public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  template <typename T>
  T get(const char* what)
  {
    T value;
    getBytes(&value, sizeof value, what);
    return value;
  }
  void getBytes(void* out, std::size_t size, const char* what)
  {
    if (size > size_ - at_)
      throw MemoryError(std::string("the bytes end inside ") + what);
    std::memcpy(out, data_ + at_, size);
    at_ += size;
  }
  /// A count of items of `item_bytes` each that the bytes left can hold.
  std::size_t count(std::size_t item_bytes, const char* what)
  {
    const auto n = get<std::uint64_t>(what);
    if (n > (size_ - at_) / item_bytes)
      throw MemoryError(std::string(what) + " counts " + std::to_string(n) + " items, more than the bytes hold");
    return static_cast<std::size_t>(n);
  }
  std::size_t left() const { return size_ - at_; }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

inline void putMatx(ByteWriter& out, const cv::Matx23d& m)
{
  for (int i = 0; i < 6; ++i)
    out.put(m.val[i]);
}

inline cv::Matx23d getMatx(ByteReader& in, const char* what)
{
  cv::Matx23d m;
  for (int i = 0; i < 6; ++i)
    m.val[i] = in.get<double>(what);
  return m;
}
}  // namespace amcr
