#include "image_input.h"

#include <sensor_msgs/image_encodings.h>

namespace amcr_ros
{
namespace enc = sensor_msgs::image_encodings;

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
    if (enc::isColor(e) || enc::isMono(e) || enc::isBayer(e) || e == enc::YUV422 || e == enc::BGRA8)
    {
      const std::size_t row = static_cast<std::size_t>(msg->width) * enc::numChannels(e) * (enc::bitDepth(e) / 8);
      if (msg->step < row || msg->data.size() < static_cast<std::size_t>(msg->step) * msg->height)
      {
        why = "inconsistent image: " + std::to_string(msg->width) + " x " + std::to_string(msg->height) + " '" + e +
              "' with step " + std::to_string(msg->step) + " and " + std::to_string(msg->data.size()) + " bytes";
        return nullptr;
      }
    }
    if (e == enc::MONO8 || e == enc::MONO16 || e == enc::BGR8 || e == enc::BGRA8)
      return cv_bridge::toCvShare(msg);  // read as they are by the core
    if (enc::isColor(e) || enc::isBayer(e) || e == enc::YUV422)
      return cv_bridge::toCvShare(msg, enc::BGR8);
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
