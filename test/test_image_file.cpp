// Image files (libjpeg decodes a truncated JPEG with a grey lower part and
// only prints a line): a JPEG or PNG that is truncated or has a
// broken marker or chunk length is refused with an InputError naming the
// file and the damage, as a prototype (skipped with a warning) and as a
// file read alone; the intact file is read as OpenCV reads it.
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "amcr/base/errors.h"
#include "amcr/io/image_file.h"
#include "amcr/memory/prototype_memory.h"
#include "scene_drawing.h"

namespace
{
using Bytes = std::vector<unsigned char>;

Bytes encode(const std::string& extension, const cv::Mat& image)
{
  Bytes bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes));
  return bytes;
}

void writeBytes(const std::string& path, const Bytes& bytes)
{
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// The InputError message of reading `path`, or "" when it was read.
std::string readError(const std::string& path)
{
  try
  {
    amcr::readImageFile(path);
  }
  catch (const amcr::InputError& e)
  {
    return e.what();
  }
  return "";
}

/// Offset of the first JPEG marker `marker` (its 0xFF) in `bytes`.
std::size_t jpegMarker(const Bytes& bytes, unsigned char marker)
{
  for (std::size_t i = 2; i + 1 < bytes.size(); ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] == marker)
      return i;
  ADD_FAILURE() << "no marker " << int(marker);
  return 0;
}

const cv::Mat& arrow()
{
  static const cv::Mat image = amcr_test::drawPrototype(amcr_test::ShapeId::kArrow);
  return image;
}

TEST(ImageFile, IntactJpegAndPngAreReadAsOpenCvReadsThem)
{
  amcr_test::TempDir dir;
  for (const std::string ext : {".jpg", ".png"})
  {
    const std::string path = dir.file("arrow" + ext);
    writeBytes(path, encode(ext, arrow()));
    const cv::Mat read = amcr::readImageFile(path);
    const cv::Mat expected = cv::imread(path, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(read.size(), expected.size()) << ext;
    EXPECT_EQ(cv::norm(read, expected, cv::NORM_INF), 0.0) << ext;
  }
  // Bytes after the JPEG's end-of-image marker (padding) are allowed.
  Bytes padded = encode(".jpg", arrow());
  padded.insert(padded.end(), 64, 0x00);
  writeBytes(dir.file("padded.jpg"), padded);
  EXPECT_EQ(readError(dir.file("padded.jpg")), "");
}

TEST(ImageFile, TruncatedJpegIsRefusedNamingTheFileAndTheDamage)
{
  amcr_test::TempDir dir;
  const Bytes whole = encode(".jpg", arrow());
  for (std::size_t cut : {std::size_t(1), std::size_t(2), std::size_t(100), whole.size() / 2, whole.size() - 200})
  {
    const std::string path = dir.file("cut_" + std::to_string(cut) + ".jpg");
    writeBytes(path, Bytes(whole.begin(), whole.end() - static_cast<long>(cut)));
    const std::string error = readError(path);
    EXPECT_NE(error.find("truncated JPEG"), std::string::npos) << "cut by " << cut << ": '" << error << "'";
    EXPECT_NE(error.find(path), std::string::npos) << error;
  }
  writeBytes(dir.file("cut.jpg"), Bytes(whole.begin(), whole.end() - 1));
  EXPECT_NE(readError(dir.file("cut.jpg")).find("no end-of-image marker"), std::string::npos);
}

TEST(ImageFile, JpegWithACorruptMarkerLengthIsRefused)
{
  amcr_test::TempDir dir;
  const Bytes whole = encode(".jpg", arrow());
  for (unsigned char marker : {0xDB /* DQT */, 0xC4 /* DHT */, 0xC0 /* SOF0 */})
  {
    Bytes bytes = whole;
    const std::size_t at = jpegMarker(bytes, marker);
    bytes[at + 3] = static_cast<unsigned char>(bytes[at + 3] + 1);  // length one byte too long
    const std::string path = dir.file("marker_" + std::to_string(marker) + ".jpg");
    writeBytes(path, bytes);
    EXPECT_NE(readError(path).find("damaged JPEG"), std::string::npos) << int(marker) << ": " << readError(path);
  }
  Bytes huge = whole;
  const std::size_t at = jpegMarker(huge, 0xDB);
  huge[at + 2] = 0xFF;  // a length past the end of the file
  writeBytes(dir.file("huge_length.jpg"), huge);
  EXPECT_NE(readError(dir.file("huge_length.jpg")).find("JPEG"), std::string::npos);
}

TEST(ImageFile, TruncatedOrDamagedPngIsRefused)
{
  amcr_test::TempDir dir;
  const Bytes whole = encode(".png", arrow());
  writeBytes(dir.file("cut.png"), Bytes(whole.begin(), whole.end() - 5));
  EXPECT_NE(readError(dir.file("cut.png")).find("truncated PNG"), std::string::npos) << readError(dir.file("cut.png"));
  Bytes bad_length = whole;
  bad_length[8 + 3] = 14;  // IHDR's length 13 -> 14
  writeBytes(dir.file("length.png"), bad_length);
  EXPECT_NE(readError(dir.file("length.png")).find("damaged PNG"), std::string::npos) << readError(dir.file("length.png"));
}

TEST(ImageFile, MissingEmptyDirectoryAndForeignFilesAreRefusedWithTheReason)
{
  amcr_test::TempDir dir;
  EXPECT_NE(readError(dir.file("none.png")).find("No such file"), std::string::npos) << readError(dir.file("none.png"));
  EXPECT_NE(readError(dir.path()).find("directory"), std::string::npos) << readError(dir.path());
  writeBytes(dir.file("empty.png"), Bytes());
  EXPECT_NE(readError(dir.file("empty.png")).find("empty"), std::string::npos);
  std::ofstream(dir.file("notes.txt")) << "not an image\n";
  EXPECT_NE(readError(dir.file("notes.txt")).find("notes.txt"), std::string::npos);
}

TEST(ImageFile, ImageAboveThePixelBoundIsRefusedFromItsHeader)
{
  amcr_test::TempDir dir;
  Bytes png = encode(".png", arrow());
  // IHDR width and height (bytes 16-23) set to 10000 x 10000, not decoded.
  const unsigned char side[] = {0x00, 0x00, 0x27, 0x10};
  std::copy(side, side + 4, png.begin() + 16);
  std::copy(side, side + 4, png.begin() + 20);
  writeBytes(dir.file("big.png"), png);
  const std::string error = readError(dir.file("big.png"));
  EXPECT_NE(error.find("100000000 pixels"), std::string::npos) << error;
  EXPECT_NE(error.find("33177600"), std::string::npos) << error;
}

TEST(ImageFile, DamagedPrototypeFilesAreSkippedWithAWarning)
{
  amcr_test::TempDir dir;
  const Bytes jpeg = encode(".jpg", amcr_test::drawPrototype(amcr_test::ShapeId::kStar));
  writeBytes(dir.file("star.jpg"), Bytes(jpeg.begin(), jpeg.end() - 300));
  writeBytes(dir.file("arrow.jpg"), encode(".jpg", arrow()));
  std::vector<std::string> warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(
      dir.path(), amcr::Params(), [&](const std::string& line) { warnings.push_back(line); });
  ASSERT_EQ(memory.size(), 1u);
  EXPECT_EQ(memory[0].label(), "arrow");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("star.jpg"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("truncated JPEG"), std::string::npos) << warnings[0];
}
}  // namespace
