#include "prototype_image.h"

#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "amcr/memory/edge_model.h"

namespace amcr_bench
{
PrototypeImage prototypeImage(const std::string& label, const cv::Mat& image)
{
  PrototypeImage p{label, {}, {}};
  cv::Mat grey, alpha;
  try
  {
    amcr::prototypeGreyAndAlpha(image, grey, alpha);  // as amcr::Prototype reads it
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument("prototype '" + label + "': " + e.what());
  }
  double lo = 0, hi = 0;
  cv::minMaxLoc(grey, &lo, &hi);
  const bool flat = hi - lo < 1.0;
  if ((flat && alpha.empty()) || !amcr::readAsTemplate(grey, alpha))
  {
    p.mask = grey;
    return p;
  }
  p.grey = grey;
  p.mask = alpha.empty() ? cv::Mat(grey.size(), CV_8UC1, cv::Scalar(255)) : cv::Mat(alpha >= 128);
  return p;
}

PrototypeImage readPrototypeImage(const std::string& label, const std::string& path)
{
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty())
    throw std::invalid_argument("cannot read the prototype image " + path);
  PrototypeImage p;
  try
  {
    p = prototypeImage(label, image);
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(path + ": " + e.what());
  }
  if (!p.isTemplate())
    p.mask = cv::imread(path, cv::IMREAD_GRAYSCALE);
  return p;
}
}  // namespace amcr_bench
