#include "amcr/scan/radial_scan.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"

namespace amcr
{
RadialScanner::RadialScanner(const cv::Mat& smoothed, double threshold, double max_length)
  : RadialScanner(smoothed, threshold, max_length, cv::Mat())
{
}

RadialScanner::RadialScanner(const cv::Mat& smoothed, double threshold, double max_length, const cv::Mat& free_space)
  : image_(smoothed)
  , free_space_(free_space)
  , thresholds_(threshold)
  , max_length_(static_cast<float>(max_length))
{
  checkInputs();
}

RadialScanner::RadialScanner(const cv::Mat& smoothed, const EdgeThresholds& thresholds, double max_length)
  : image_(smoothed), thresholds_(thresholds), max_length_(static_cast<float>(max_length))
{
  checkInputs();
}

void RadialScanner::checkInputs()
{
  if (image_.type() != CV_8UC1)
    throw InputError("RadialScanner needs an 8-bit grey image, got " + cv::typeToString(image_.type()));
  if (!free_space_.empty() && (free_space_.type() != CV_32FC1 || free_space_.size() != image_.size()))
    throw InputError("RadialScanner: the free-space map must be CV_32FC1 of the image's size");
  if (!free_space_.empty() && !free_space_.isContinuous())
    free_space_ = free_space_.clone();
  data_ = image_.ptr<uchar>(0);
  step_ = image_.step[0];
  cols_ = image_.cols;
  rows_ = image_.rows;
  max_x_ = static_cast<float>(cols_ - 1);
  max_y_ = static_cast<float>(rows_ - 1);
  free_ = free_space_.empty() ? nullptr : free_space_.ptr<float>(0);
}

RayHit RadialScanner::scan(float x, float y, float dx, float dy) const
{
  RayHit hit;
  auto inside = [&](float t) { return contains(x + t * dx, y + t * dy); };
  if (!inside(0.f))
    return hit;
  const float threshold = thresholds_.at(x, y);
  const int steps = static_cast<int>(max_length_);
  // previous, current and next sample along the ray: the step at t is
  // |I(t+1) - I(t-1)|.
  float before = sample(x, y);  // t - 1 (clamped at the origin for t = 1)
  float current = before;
  if (!inside(1.f))
    return hit;
  current = sample(x + dx, y + dy);
  float last_step = 0.f;  // the step at t - 1
  for (int t = 1; t < steps; ++t)
  {
    const int skip = leap(x + t * dx, y + t * dy);
    if (skip > 0)
    {
      // No step from t to t + skip - 1 can reach the threshold: leap, then
      // take up the samples around the new t.
      t += skip;
      if (t >= steps || !inside(static_cast<float>(t)))
        return hit;
      const float tf = static_cast<float>(t);
      before = sample(x + (tf - 1) * dx, y + (tf - 1) * dy);
      current = sample(x + tf * dx, y + tf * dy);
      last_step = std::abs(current - sample(x + (tf - 2) * dx, y + (tf - 2) * dy));
    }
    const float tn = static_cast<float>(t + 1);
    if (!inside(tn))
      return hit;
    const float next = sample(x + tn * dx, y + tn * dy);
    const float step = std::abs(next - before);
    if (step >= threshold)
      return peakOfRun(x, y, dx, dy, t, steps, last_step, step, current, next);
    last_step = step;
    before = current;
    current = next;
  }
  return hit;
}

// Follows the run of large steps that starts at t (step `step`, the step
// before it `last_step`, samples `current` at t and `next` at t + 1) to its
// largest step, then refines the edge's place with a parabola.
RayHit RadialScanner::peakOfRun(float x, float y, float dx, float dy, int t, int steps, float last_step, float step,
                                float current, float next) const
{
  RayHit hit;
  float prev_step = last_step;
  int best_t = t;
  float best = step;
  float b = current, c = next;
  for (int u = t + 1; u < steps; ++u)
  {
    const float un = static_cast<float>(u + 1);
    if (!contains(x + un * dx, y + un * dy))
      break;
    const float n = sample(x + un * dx, y + un * dy);
    const float s = std::abs(n - b);
    if (s <= best)
    {
      const float denom = prev_step - 2.f * best + s;
      const float offset = denom < 0.f ? 0.5f * (prev_step - s) / denom : 0.f;
      hit.valid = true;
      hit.distance = best_t + std::max(-0.5f, std::min(0.5f, offset));
      return hit;
    }
    prev_step = best;
    best = s;
    best_t = u;
    b = c;
    c = n;
  }
  hit.valid = true;
  hit.distance = static_cast<float>(best_t);
  return hit;
}

RayHit RadialScanner::scanAngle(float x, float y, double angle) const
{
  return scan(x, y, static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
}

cv::Point2f RadialScanner::edgeNormal(float x, float y) const
{
  const int cx = std::min(std::max(static_cast<int>(std::lround(x)), 1), image_.cols - 2);
  const int cy = std::min(std::max(static_cast<int>(std::lround(y)), 1), image_.rows - 2);
  if (image_.cols < 3 || image_.rows < 3)
    return {0.f, 0.f};
  // Sobel at the nearest pixel.
  auto at = [&](int xx, int yy) { return static_cast<float>(image_.at<uchar>(yy, xx)); };
  const float gx = (at(cx + 1, cy - 1) + 2 * at(cx + 1, cy) + at(cx + 1, cy + 1)) -
                   (at(cx - 1, cy - 1) + 2 * at(cx - 1, cy) + at(cx - 1, cy + 1));
  const float gy = (at(cx - 1, cy + 1) + 2 * at(cx, cy + 1) + at(cx + 1, cy + 1)) -
                   (at(cx - 1, cy - 1) + 2 * at(cx, cy - 1) + at(cx + 1, cy - 1));
  const float norm = std::hypot(gx, gy);
  if (norm < 1e-3f)
    return {0.f, 0.f};
  return {gx / norm, gy / norm};
}

cv::Mat toGray8(const cv::Mat& image)
{
  if (image.empty())
    throw InputError("the image is empty (0 x 0 pixels)");
  const int channels = image.channels();
  if (channels != 1 && channels != 3 && channels != 4)
    throw InputError("unsupported image type " + cv::typeToString(image.type()) +
                     ": expected 1 (grey), 3 (BGR) or 4 (BGRA) channels");
  // First the depth, then the channels (cvtColor takes 8-bit, 16-bit and 32F only).
  cv::Mat depth8;
  switch (image.depth())
  {
    case CV_8U:
      depth8 = image;
      break;
    case CV_16U:
      image.convertTo(depth8, CV_8U, 1.0 / 257.0);
      break;
    case CV_32F:
    case CV_64F:
    {
      // Float images are taken as [0, 1] when their maximum is at most 1, else as [0, 255].
      double lo = 0, hi = 0;
      cv::minMaxLoc(image.reshape(1), &lo, &hi);
      if (!std::isfinite(lo) || !std::isfinite(hi))
        throw InputError("the " + cv::typeToString(image.type()) + " image holds NaN or infinite values");
      image.convertTo(depth8, CV_8U, hi <= 1.0 ? 255.0 : 1.0);
      break;
    }
    default:
      throw InputError("unsupported image type " + cv::typeToString(image.type()) +
                       ": expected 8-bit, 16-bit unsigned or floating-point pixels");
  }
  if (channels == 1)
    return depth8;
  cv::Mat grey;
  cv::cvtColor(depth8, grey, channels == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  return grey;
}

cv::Mat prepareScanImage(const cv::Mat& image, double blur_sigma)
{
  cv::Mat grey = toGray8(image);
  if (blur_sigma <= 0.0)
    return grey.clone();
  cv::Mat smoothed;
  cv::GaussianBlur(grey, smoothed, cv::Size(0, 0), blur_sigma, blur_sigma, cv::BORDER_REPLICATE);
  return smoothed;
}
}  // namespace amcr
