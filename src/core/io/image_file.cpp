// Image files: the file checks, the walk over a JPEG's markers and a PNG's
// chunks, then cv::imdecode (image_file.h says what is and is not detected).
#include "amcr/io/image_file.h"

#include <cerrno>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "amcr/base/errors.h"
#include "amcr/base/resource_bounds.h"

namespace amcr
{
namespace
{
namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

std::size_t bigEndian16(const Bytes& b, std::size_t at) { return (std::size_t(b[at]) << 8) | b[at + 1]; }

std::size_t bigEndian32(const Bytes& b, std::size_t at)
{
  return (bigEndian16(b, at) << 16) | bigEndian16(b, at + 2);
}

std::string hexByte(unsigned value)
{
  static const char kDigits[] = "0123456789ABCDEF";
  return std::string("0x") + kDigits[(value >> 4) & 15] + kDigits[value & 15];
}

bool isStartOfFrame(unsigned marker)
{
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

/// After the first SOS: entropy-coded data (0xFF only before 0x00, a fill
/// 0xFF or a restart marker) and, in a progressive JPEG, marker segments
/// between the scans, up to the EOI.
void checkJpegScans(const Bytes& b, std::size_t pos, const std::string& what)
{
  const std::size_t n = b.size();
  while (pos + 1 < n)
  {
    const unsigned marker = b[pos + 1];
    if (b[pos] != 0xFF || marker == 0x00 || marker == 0xFF || (marker >= 0xD0 && marker <= 0xD7))
    {
      ++pos;
      continue;
    }
    if (marker == 0xD9)
      return;
    if (pos + 4 > n)
      break;
    const std::size_t length = bigEndian16(b, pos + 2);
    if (length < 2)
      throw InputError("damaged JPEG " + what + ": the segment " + hexByte(marker) + " at byte " +
                       std::to_string(pos) + " has length " + std::to_string(length));
    pos += 2 + length;
  }
  throw InputError("truncated JPEG " + what + ": no end-of-image marker after the scan data");
}

/// From SOI to the first SOS: each marker segment starts with 0xFF and fits
/// in the file; a frame header (SOF) gives the image size.
void checkJpeg(const Bytes& b, const std::string& what)
{
  const std::size_t n = b.size();
  std::size_t pos = 2;
  bool have_frame = false;
  while (true)
  {
    if (pos >= n)
      throw InputError("truncated JPEG " + what + ": the file ends before the image data");
    if (b[pos] != 0xFF)
      throw InputError("damaged JPEG " + what + ": no marker at byte " + std::to_string(pos) +
                       " (the length of the segment before it is wrong)");
    while (pos < n && b[pos] == 0xFF)
      ++pos;
    if (pos + 2 >= n)
      throw InputError("truncated JPEG " + what + ": the file ends before the image data");
    const unsigned marker = b[pos++];
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01)
      continue;  // markers without a segment
    if (marker == 0x00 || marker == 0xD8 || marker == 0xD9)
      throw InputError("damaged JPEG " + what + ": marker " + hexByte(marker) + " at byte " + std::to_string(pos - 1) +
                       " before the image data");
    const std::size_t length = bigEndian16(b, pos);
    if (length < 2 || pos + length > n)
      throw InputError(std::string(length < 2 ? "damaged" : "truncated") + " JPEG " + what + ": the segment " +
                       hexByte(marker) + " at byte " + std::to_string(pos - 2) + " has length " +
                       std::to_string(length) + ", the file has " + std::to_string(n - pos) + " bytes after it");
    if (isStartOfFrame(marker) && length >= 7)
    {
      const std::size_t height = bigEndian16(b, pos + 3), width = bigEndian16(b, pos + 5);
      if (width == 0)
        throw InputError("damaged JPEG " + what + ": its frame header gives a width of 0");
      checkImageBound(width, height, "the JPEG " + what);
      have_frame = true;
    }
    if (marker == 0xDA)
    {
      if (!have_frame)
        throw InputError("damaged JPEG " + what + ": image data without a frame header (SOF)");
      return checkJpegScans(b, pos + length, what);
    }
    pos += length;
  }
}

/// From the signature to IEND: each chunk (length, type, data, CRC) fits in
/// the file; the first is IHDR, which gives the image size.
void checkPng(const Bytes& b, const std::string& what)
{
  const std::size_t n = b.size();
  std::size_t pos = 8;
  while (pos + 8 <= n)
  {
    const std::size_t length = bigEndian32(b, pos);
    const std::string type(b.begin() + pos + 4, b.begin() + pos + 8);
    for (char c : type)
      if (!std::isalpha(static_cast<unsigned char>(c)))
        throw InputError("damaged PNG " + what + ": no chunk at byte " + std::to_string(pos) +
                         " (the length of the chunk before it is wrong)");
    if (length > 0x7FFFFFFFu || pos + 12 + length > n)
      throw InputError("truncated PNG " + what + ": the chunk " + type + " at byte " + std::to_string(pos) +
                       " has " + std::to_string(length) + " bytes of data, the file ends before");
    if (pos == 8)
    {
      if (type != "IHDR" || length != 13)
        throw InputError("damaged PNG " + what + ": its first chunk is not a 13-byte IHDR");
      checkImageBound(bigEndian32(b, pos + 8), bigEndian32(b, pos + 12), "the PNG " + what);
    }
    if (type == "IEND")
      return;
    pos += 12 + length;
  }
  throw InputError("truncated PNG " + what + ": no IEND chunk at the end");
}
}  // namespace

void checkImageBytes(const Bytes& bytes, const std::string& what)
{
  static const unsigned char kPng[] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF)
    checkJpeg(bytes, what);
  else if (bytes.size() >= 8 && std::memcmp(bytes.data(), kPng, 8) == 0)
    checkPng(bytes, what);
}

Bytes readImageFileBytes(const std::string& path)
{
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error)
    throw InputError("cannot read image '" + path + "': " + error.message());
  if (fs::is_directory(status))
    throw InputError("cannot read image '" + path + "': it is a directory");
  if (!fs::is_regular_file(status))
    throw InputError("cannot read image '" + path + "': not a regular file");
  const std::uintmax_t size = fs::file_size(path, error);
  if (!error && size > static_cast<std::uintmax_t>(kMaxImageFileBytes))
    throw InputError("cannot read image '" + path + "': the file has " + std::to_string(size) +
                     " bytes, above the bound of " + std::to_string(kMaxImageFileBytes) + " bytes");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError("cannot read image '" + path + "': " + (errno ? std::strerror(errno) : "cannot open it"));
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw InputError("cannot read image '" + path + "': a read error");
  return bytes;
}

cv::Mat readImageFile(const std::string& path, int flags) { return decodeImageFile(readImageFileBytes(path), path, flags); }

cv::Mat decodeImageFile(const Bytes& bytes, const std::string& path, int flags)
{
  const std::string what = "'" + path + "'";
  if (bytes.empty())
    throw InputError("cannot read image " + what + ": the file is empty");
  checkImageBytes(bytes, what);
  cv::Mat image;
  try
  {
    image = cv::imdecode(bytes, flags);
  }
  catch (const cv::Exception& e)
  {
    throw InputError("cannot decode image " + what + ": " + e.err);
  }
  if (image.empty())
    throw InputError("cannot read image " + what + ": not an image format OpenCV reads, or damaged data");
  checkImageBound(image.cols, image.rows, "the image " + what);
  return image;
}
}  // namespace amcr
