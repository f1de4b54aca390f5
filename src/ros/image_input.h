// Which sensor_msgs/Image encodings the recognizer takes, and how: the core
// reads 8/16-bit grey and BGR/BGRA directly; other colour, Bayer and YUV
// encodings are converted to bgr8 by cv_bridge; everything else (depth, float,
// multi-channel data) is refused with a message naming the encoding.
#pragma once

#include <string>

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/Image.h>

namespace amcr_ros
{
/// The image as the core takes it. Returns null and sets `why` when the image
/// cannot be used (zero size, unsupported encoding, inconsistent data).
/// Never throws.
cv_bridge::CvImageConstPtr toCoreImage(const sensor_msgs::ImageConstPtr& msg, std::string& why);
}  // namespace amcr_ros
