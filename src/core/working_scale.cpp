#include "amcr/working_scale.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/base/homography.h"
#include "amcr/extraction/viewing_angle.h"

namespace amcr
{
double WorkingScale::factor() const
{
  const int longer_input = std::max(input.width, input.height);
  const int longer_working = std::max(working.width, working.height);
  return longer_input > 0 ? static_cast<double>(longer_working) / longer_input : 1.0;
}

Affine WorkingScale::toInput() const
{
  if (identity() || working.width <= 0 || working.height <= 0)
    return identityAffine();
  // Per axis, as cv::resize maps pixel centres: each side was rounded on its own.
  const double ax = static_cast<double>(input.width) / working.width;
  const double ay = static_cast<double>(input.height) / working.height;
  return Affine(ax, 0, 0.5 * ax - 0.5, 0, ay, 0.5 * ay - 0.5);
}

Affine WorkingScale::toWorking() const
{
  Affine inverse = identityAffine();
  invertAffine(toInput(), inverse);  // a positive diagonal: always invertible
  return inverse;
}

WorkingScale chooseWorkingScale(const cv::Size& input, int working_resolution)
{
  WorkingScale scale{input, input};
  const int longer = std::max(input.width, input.height);
  if (working_resolution <= 0 || longer <= working_resolution)
    return scale;
  const double s = static_cast<double>(working_resolution) / longer;
  const auto side = [s](int px) { return std::max(1, static_cast<int>(std::lround(px * s))); };
  scale.working = cv::Size(side(input.width), side(input.height));
  return scale;
}

cv::Mat toWorkingImage(const cv::Mat& grey, const WorkingScale& scale)
{
  if (scale.identity())
    return grey;
  cv::Mat working;
  cv::resize(grey, working, scale.working, 0, 0, cv::INTER_AREA);
  return working;
}

void scaleResult(RecognitionResult& result, const Affine& working_to_input)
{
  for (RecognizedObject& o : result.objects)
    mapImageSide(o, working_to_input);
  for (RecognizedObject& o : result.lost)
    mapImageSide(o, working_to_input);
}
}  // namespace amcr
