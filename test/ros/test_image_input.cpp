// amcr_ros::toCoreImage on plain sensor_msgs::Image values (no master): what the
// recognizer reads, and the one-line reason when it cannot.
#include <cstdint>
#include <string>

#include <boost/make_shared.hpp>
#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include "image_input.h"

namespace
{
namespace enc = sensor_msgs::image_encodings;

/// A `width` x `height` image of `encoding` whose rows are `step` bytes, every byte `fill`.
sensor_msgs::ImagePtr image(const std::string& encoding, std::uint32_t width, std::uint32_t height,
                            std::uint32_t step, std::uint8_t fill = 0)
{
  auto msg = boost::make_shared<sensor_msgs::Image>();
  msg->encoding = encoding;
  msg->width = width;
  msg->height = height;
  msg->step = step;
  msg->data.assign(static_cast<std::size_t>(step) * height, fill);
  return msg;
}

/// toCoreImage's reason for refusing `msg`; a failure when it is accepted.
std::string refusal(const sensor_msgs::ImageConstPtr& msg)
{
  std::string why;
  const cv_bridge::CvImageConstPtr converted = amcr_ros::toCoreImage(msg, why);
  EXPECT_FALSE(converted) << msg->encoding << " accepted";
  EXPECT_FALSE(why.empty());
  return why;
}

TEST(ImageInput, ReadsMonoAndColourAsTheyAre)
{
  std::string why;
  const auto mono = amcr_ros::toCoreImage(image(enc::MONO8, 4, 3, 4, 7), why);
  ASSERT_TRUE(mono) << why;
  EXPECT_EQ(mono->image.type(), CV_8UC1);
  EXPECT_EQ(mono->image.at<std::uint8_t>(2, 3), 7);
  const auto rgb = amcr_ros::toCoreImage(image(enc::RGB8, 4, 3, 12), why);
  ASSERT_TRUE(rgb) << why;
  EXPECT_EQ(rgb->image.type(), CV_8UC3);
}

// cv_bridge hands a big-endian mono16 image back as two 8-bit channels ("unsupported image type
// CV_8UC2" further on): it is read in the host's byte order instead.
TEST(ImageInput, BigEndianMono16IsReadInHostOrder)
{
  for (const bool big : {false, true})
  {
    auto msg = image(enc::MONO16, 3, 2, 6);
    msg->is_bigendian = big;
    for (std::size_t i = 0; i < msg->data.size(); i += 2)
    {
      msg->data[i] = big ? 0x12 : 0x34;
      msg->data[i + 1] = big ? 0x34 : 0x12;
    }
    std::string why;
    const auto converted = amcr_ros::toCoreImage(msg, why);
    ASSERT_TRUE(converted) << (big ? "big" : "little") << "-endian: " << why;
    EXPECT_EQ(converted->image.type(), CV_16UC1);
    EXPECT_EQ(converted->image.at<std::uint16_t>(1, 2), 0x1234) << (big ? "big" : "little") << "-endian";
  }
}

// A mono16 row of an odd number of bytes: OpenCV said only "Step must be a multiple of esz1".
TEST(ImageInput, AStepThatIsNotAWholeNumberOfElementsIsNamed)
{
  const std::string why = refusal(image(enc::MONO16, 4, 3, 9));
  for (const char* part : {"mono16", "step 9", "multiple of its 2-byte element"})
    EXPECT_NE(why.find(part), std::string::npos) << part << " not in: " << why;
  EXPECT_EQ(why.find("esz1"), std::string::npos) << why;
}

TEST(ImageInput, BadSizesDataAndEncodingsAreNamed)
{
  EXPECT_NE(refusal(image(enc::MONO8, 0, 3, 0)).find("zero-size"), std::string::npos);
  auto truncated = image(enc::MONO8, 4, 3, 4);
  truncated->data.resize(5);
  EXPECT_NE(refusal(truncated).find("5 bytes"), std::string::npos);
  EXPECT_NE(refusal(image(enc::MONO16, 4, 3, 6)).find("step 6"), std::string::npos) << "a row longer than the step";
  EXPECT_NE(refusal(image(enc::TYPE_32FC1, 4, 3, 16)).find("unsupported encoding '32FC1'"), std::string::npos);
}
}  // namespace
