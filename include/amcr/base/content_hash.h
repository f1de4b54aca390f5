// A 64-bit hash of bytes for the table cache (table_cache.h): FNV-1a's
// offset basis and prime, applied to 8-byte words and then to the bytes
// left over, so that a 2 MB table is hashed at memory speed. Not a
// cryptographic hash: it names content and detects damage, it does not
// resist a forger. Every step (xor a word, multiply by an odd prime) is a
// bijection of the state, so two inputs of one length that differ in a
// single word always hash differently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace amcr
{
class ContentHash
{
public:
  static constexpr std::uint64_t kOffsetBasis = 14695981039346656037ull;
  static constexpr std::uint64_t kPrime = 1099511628211ull;

  ContentHash& add(const void* data, std::size_t size)
  {
    const auto* bytes = static_cast<const unsigned char*>(data);
    std::size_t i = 0;
    for (; i + 8 <= size; i += 8)
    {
      std::uint64_t word;
      std::memcpy(&word, bytes + i, 8);
      state_ = (state_ ^ word) * kPrime;
    }
    for (; i < size; ++i)
      state_ = (state_ ^ bytes[i]) * kPrime;
    // The length closes each piece: "ab" + "c" and "a" + "bc" differ.
    state_ = (state_ ^ static_cast<std::uint64_t>(size)) * kPrime;
    return *this;
  }

  /// A number or a plain struct, by its bytes.
  template <typename T>
  ContentHash& addValue(const T& value)
  {
    return add(&value, sizeof value);
  }

  ContentHash& addText(const std::string& text) { return add(text.data(), text.size()); }

  std::uint64_t value() const { return state_; }

private:
  std::uint64_t state_ = kOffsetBasis;
};

/// The hash of one block of bytes.
inline std::uint64_t hashBytes(const void* data, std::size_t size) { return ContentHash().add(data, size).value(); }
}  // namespace amcr
