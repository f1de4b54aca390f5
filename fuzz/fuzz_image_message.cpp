// The image-message conversion of the nodelet: bytes -> sensor_msgs::Image -> amcr_ros::toCoreImage
// (src/ros/image_input.cpp) -> amcr::toGray8, what RecognizerRos does with each image.
//
// Input layout: byte 0 picks the encoding from kEncodings (past its end: byte 1 is a length and
// that many bytes are the encoding's name); then width, height and step as little-endian u32,
// one byte is_bigendian, and the rest is the data. A refusal (null with a reason, InputError) is
// an accepted answer; an exception out of toCoreImage, a null without a reason, or a sanitizer
// report is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include <boost/make_shared.hpp>
#include <sensor_msgs/Image.h>

#include "amcr/base/errors.h"
#include "amcr/scan/radial_scan.h"
#include "fuzz_input.h"
#include "image_input.h"

namespace
{
const char* const kEncodings[] = {
  "mono8",        "mono16",       "bgr8",         "rgb8",         "bgra8",        "rgba8",        "bgr16",
  "rgb16",        "bgra16",       "rgba16",       "bayer_rggb8",  "bayer_bggr8",  "bayer_gbrg8",  "bayer_grbg8",
  "bayer_rggb16", "bayer_bggr16", "bayer_gbrg16", "bayer_grbg16", "yuv422",       "8UC1",         "8UC2",
  "8UC3",         "8UC4",         "8SC1",         "16UC1",        "16UC3",        "16SC1",        "32SC1",
  "32FC1",        "32FC3",        "64FC1",        "16FC1",        "",             "nv21",         "yuv422_yuy2",
};
constexpr std::size_t kEncodingCount = sizeof(kEncodings) / sizeof(kEncodings[0]);
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  amcr_fuzz::setUpOpenCv();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  amcr_fuzz::ByteReader in(data, size);
  auto msg = boost::make_shared<sensor_msgs::Image>();
  const std::size_t pick = in.byte();
  msg->encoding = pick < kEncodingCount ? kEncodings[pick] : in.text(in.byte());
  msg->width = in.u32();
  msg->height = in.u32();
  msg->step = in.u32();
  msg->is_bigendian = in.byte();
  msg->data.assign(in.rest(), in.rest() + in.restSize());

  std::string why;
  const cv_bridge::CvImageConstPtr image = amcr_ros::toCoreImage(msg, why);
  if (!image)
  {
    if (why.empty())
      std::abort();  // refused without a reason
    return 0;
  }
  try
  {
    const cv::Mat grey = amcr::toGray8(image->image);
    if (grey.type() != CV_8UC1 || grey.cols != static_cast<int>(msg->width) ||
        grey.rows != static_cast<int>(msg->height))
      std::abort();  // not the grey image of the message
  }
  catch (const amcr::InputError&)
  {
  }
  return 0;
}
