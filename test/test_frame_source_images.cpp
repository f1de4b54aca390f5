// The offline runner's image files (libjpeg decodes a truncated JPEG with a
// grey lower part and only prints a line): a damaged JPEG in a
// directory input is a skipped frame whose problem names the file and the
// damage; a damaged JPEG as the one input is refused, naming the damage.
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "frame_source.h"
#include "scene_drawing.h"

namespace
{
void writeJpeg(const std::string& path, const cv::Mat& image, std::size_t cut)
{
  std::vector<unsigned char> bytes;
  ASSERT_TRUE(cv::imencode(".jpg", image, bytes));
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size() - cut));
}

TEST(FrameSourceImages, TruncatedJpegInADirectoryIsASkippedFrameNamingTheDamage)
{
  amcr_test::TempDir dir;
  const cv::Mat image = amcr_test::drawPrototype(amcr_test::ShapeId::kArrow);
  writeJpeg(dir.file("0.jpg"), image, 0);
  writeJpeg(dir.file("1.jpg"), image, 400);
  writeJpeg(dir.file("2.jpg"), image, 0);
  auto source = amcr::offline::FrameSource::open(dir.path(), 10, true);
  amcr::offline::Frame frame;
  std::vector<std::string> problems;
  while (source->next(frame))
    problems.push_back(frame.image.empty() ? frame.problem : "");
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0], "");
  EXPECT_NE(problems[1].find("truncated JPEG"), std::string::npos) << problems[1];
  EXPECT_NE(problems[1].find("1.jpg"), std::string::npos) << problems[1];
  EXPECT_EQ(problems[2], "");
}

TEST(FrameSourceImages, TruncatedJpegAsTheInputIsRefusedNamingTheDamage)
{
  amcr_test::TempDir dir;
  writeJpeg(dir.file("cut.jpg"), amcr_test::drawPrototype(amcr_test::ShapeId::kStar), 1);
  try
  {
    amcr::offline::FrameSource::open(dir.file("cut.jpg"), 10, true);
    ADD_FAILURE() << "no SourceError";
  }
  catch (const amcr::offline::SourceError& e)
  {
    EXPECT_NE(std::string(e.what()).find("truncated JPEG"), std::string::npos) << e.what();
  }
}
}  // namespace
