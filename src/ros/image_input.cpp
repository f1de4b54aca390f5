#include "image_input.h"

#include <algorithm>
#include <cstdint>

#include <boost/endian/conversion.hpp>
#include <boost/make_shared.hpp>
#include <sensor_msgs/image_encodings.h>

namespace amcr_ros
{
namespace enc = sensor_msgs::image_encodings;

namespace
{
std::string describe(const sensor_msgs::Image& msg)
{
  return std::to_string(msg.width) + " x " + std::to_string(msg.height) + " '" + msg.encoding + "'";
}

/// Why the layout of an image of a known encoding cannot be read: a row longer than the step, a step that
/// is not a whole number of elements (OpenCV's "Step must be a multiple of esz1"), or too little data.
/// Empty when the layout is sound.
std::string layoutProblem(const sensor_msgs::Image& msg)
{
  const std::size_t element = static_cast<std::size_t>(enc::bitDepth(msg.encoding) / 8);
  const std::size_t row = static_cast<std::size_t>(msg.width) * enc::numChannels(msg.encoding) * element;
  if (msg.step < row || msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height)
    return "inconsistent image: " + describe(msg) + " with step " + std::to_string(msg.step) + " and " +
           std::to_string(msg.data.size()) + " bytes";
  if (element > 1 && msg.step % element != 0)
    return "inconsistent image: " + describe(msg) + " with step " + std::to_string(msg.step) +
           ", which is not a multiple of its " + std::to_string(element) + "-byte element";
  return "";
}

/// A copy of `msg` with the bytes of each element in the host's order (cv_bridge does not swap a
/// big-endian mono16 image: it hands back two 8-bit channels).
sensor_msgs::ImageConstPtr inHostOrder(const sensor_msgs::ImageConstPtr& msg)
{
  const bool host_big = boost::endian::order::native == boost::endian::order::big;
  const std::size_t element = static_cast<std::size_t>(enc::bitDepth(msg->encoding) / 8);
  if (element <= 1 || static_cast<bool>(msg->is_bigendian) == host_big)
    return msg;
  auto swapped = boost::make_shared<sensor_msgs::Image>(*msg);
  swapped->is_bigendian = host_big;
  const std::size_t row = static_cast<std::size_t>(msg->width) * enc::numChannels(msg->encoding) * element;
  for (std::size_t y = 0; y < msg->height; ++y)
  {
    std::uint8_t* p = swapped->data.data() + y * msg->step;
    for (std::size_t x = 0; x + element <= row; x += element)
      std::reverse(p + x, p + x + element);
  }
  return swapped;
}
}  // namespace

cv_bridge::CvImageConstPtr toCoreImage(const sensor_msgs::ImageConstPtr& msg, std::string& why)
{
  const std::string& e = msg->encoding;
  if (msg->width == 0 || msg->height == 0)
  {
    why = "zero-size image (" + std::to_string(msg->width) + " x " + std::to_string(msg->height) + ", encoding '" +
          e + "')";
    return nullptr;
  }
  try
  {
    const bool known = enc::isColor(e) || enc::isMono(e) || enc::isBayer(e) || e == enc::YUV422 || e == enc::BGRA8;
    if (known)
    {
      why = layoutProblem(*msg);
      if (!why.empty())
        return nullptr;
    }
    if (e == enc::MONO8 || e == enc::MONO16 || e == enc::BGR8 || e == enc::BGRA8)
      return cv_bridge::toCvShare(inHostOrder(msg));  // read as they are by the core
    if (enc::isColor(e) || enc::isBayer(e) || e == enc::YUV422)
      return cv_bridge::toCvShare(inHostOrder(msg), enc::BGR8);
    why = "unsupported encoding '" + e +
          "': expected an intensity image (mono8, mono16, bgr8, rgb8, bgra8, rgba8, bayer_*, yuv422)";
  }
  catch (const std::exception& ex)  // cv_bridge::Exception, cv::Exception
  {
    why = "cannot convert image with encoding '" + e + "' (" + std::to_string(msg->width) + " x " +
          std::to_string(msg->height) + "): " + ex.what();
  }
  return nullptr;
}
}  // namespace amcr_ros
