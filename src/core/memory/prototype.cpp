#include "amcr/memory/prototype.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/memory/edge_model.h"
#include "amcr/scan/edge_thresholds.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
namespace
{
constexpr double kOutlineSpacing = 2.0;     // px between resampled outline points
constexpr std::size_t kMinTemplatePoints = 24;  // a template's edge points: fewer fix no shape

/// Foreground mask (255 = shape) of a silhouette of either polarity: the
/// background is whichever value dominates the image border.
cv::Mat silhouetteMask(const cv::Mat& grey)
{
  cv::Mat mask;
  cv::threshold(grey, mask, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const int w = mask.cols, h = mask.rows;
  long border_on = 0, border_count = 0;
  for (int x = 0; x < w; ++x)
  {
    border_on += (mask.at<uchar>(0, x) != 0) + (mask.at<uchar>(h - 1, x) != 0);
    border_count += 2;
  }
  for (int y = 0; y < h; ++y)
  {
    border_on += (mask.at<uchar>(y, 0) != 0) + (mask.at<uchar>(y, w - 1) != 0);
    border_count += 2;
  }
  if (2 * border_on > border_count)
    cv::bitwise_not(mask, mask);
  return mask;
}
}  // namespace

Prototype::Prototype(const std::string& label, const cv::Mat& image, int size, double edge_threshold,
                     double blur_sigma, int table_stride, const std::string& instance, double edge_full_strength,
                     bool keep_polarity)
  : keep_polarity_(keep_polarity),
    blur_sigma_(blur_sigma),
    label_(label),
    instance_(instance.empty() ? label : instance)
{
  if (image.empty())
    throw MemoryError("prototype '" + label + "': the image is empty");
  if (size < 8)
    throw ParameterError("parameter 'prototype_size' = " + std::to_string(size) + " is below 8 px");
  if (table_stride < 1 || table_stride > kMaxTableStride)
    throw ParameterError("parameter 'table_stride' = " + std::to_string(table_stride) + " is outside [1, " +
                         std::to_string(kMaxTableStride) + "]");
  cv::Mat grey, alpha;
  try
  {
    prototypeGreyAndAlpha(image, grey, alpha);
  }
  catch (const InputError& e)
  {
    throw MemoryError("prototype '" + label + "': " + e.what());
  }
  double lo = 0, hi = 0;
  cv::minMaxLoc(grey, &lo, &hi);
  if (hi - lo < 1.0)
    throw MemoryError("prototype '" + label + "' has no edges: the image is uniform");
  placement_.original_size = grey.size();

  const cv::Rect box = readAsTemplate(grey, alpha) ? readTemplate(grey, alpha, size, edge_threshold, edge_full_strength)
                                                   : readSilhouette(grey, size);
  const int margin = tableMargin(size);
  const int w = mask_.cols - 2 * margin, h = mask_.rows - 2 * margin;

  // Pixel-centre convention: table = (original - box.tl + 0.5) * s - 0.5 + margin.
  const double sx = static_cast<double>(w) / box.width, sy = static_cast<double>(h) / box.height;
  cv::Matx23d& to_table = placement_.original_to_table;
  to_table = cv::Matx23d(sx, 0, (0.5 - box.x) * sx - 0.5 + margin,  //
                         0, sy, (0.5 - box.y) * sy - 0.5 + margin);
  placement_.table_to_original = cv::Matx23d(1 / sx, 0, -to_table(0, 2) / sx,  //
                                             0, 1 / sy, -to_table(1, 2) / sy);

  cv::findNonZero(mask_, interior_);
  if (interior_.empty())
    throw MemoryError("prototype '" + label + "' has no edges after normalising to " + std::to_string(size) + " px");
  buildTable(table_stride, edge_threshold, edge_full_strength);
  if (!isTemplate())
    buildOutline();
}

cv::Rect Prototype::readSilhouette(const cv::Mat& grey, int size)
{
  const cv::Mat full_mask = silhouetteMask(grey);
  std::vector<cv::Point> on;
  cv::findNonZero(full_mask, on);
  if (on.empty() || on.size() == full_mask.total())
    throw MemoryError("prototype '" + label_ + "' has no edges: no shape against a background");
  const cv::Rect box = cv::boundingRect(on);

  // Normalise: the shape's longer side becomes `size` px, with a margin so
  // that rays starting just outside the shape still see it.
  const double scale = static_cast<double>(size) / std::max(box.width, box.height);
  const int w = std::max(1, static_cast<int>(std::lround(box.width * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(box.height * scale)));
  const int margin = tableMargin(size);
  cv::Mat resized;
  cv::resize(full_mask(box), resized, cv::Size(w, h), 0, 0, scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::threshold(resized, resized, 127, 255, cv::THRESH_BINARY);
  mask_ = cv::Mat::zeros(h + 2 * margin, w + 2 * margin, CV_8UC1);
  resized.copyTo(mask_(cv::Rect(margin, margin, w, h)));
  return box;
}

cv::Rect Prototype::readTemplate(const cv::Mat& grey, const cv::Mat& alpha, int size, double edge_threshold,
                                 double edge_full_strength)
{
  kind_ = PrototypeKind::kTemplate;
  cv::Rect box(0, 0, grey.cols, grey.rows);
  if (!alpha.empty())
  {
    std::vector<cv::Point> opaque;
    cv::findNonZero(alpha >= 128, opaque);
    if (opaque.empty())
      throw MemoryError("prototype '" + label_ + "': its alpha channel is transparent everywhere");
    box = cv::boundingRect(opaque);
  }
  const double scale = static_cast<double>(size) / std::max(box.width, box.height);
  const int w = std::max(1, static_cast<int>(std::lround(box.width * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(box.height * scale)));
  const int margin = tableMargin(size);
  const int interpolation = scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR;
  cv::Mat resized, padded;
  cv::resize(grey(box), resized, cv::Size(w, h), 0, 0, interpolation);
  // The template's border is no edge of the object: the margin repeats it.
  cv::copyMakeBorder(resized, padded, margin, margin, margin, margin, cv::BORDER_REPLICATE);
  template_scan_ = prepareScanImage(padded, blur_sigma_);

  cv::Mat region;  // where edge points may lie: the alpha channel and 2 px around it, else everywhere
  if (!alpha.empty())
  {
    cv::Mat resized_alpha;
    cv::resize(alpha(box), resized_alpha, cv::Size(w, h), 0, 0, interpolation);
    cv::threshold(resized_alpha, resized_alpha, 127, 255, cv::THRESH_BINARY);
    mask_ = cv::Mat::zeros(padded.size(), CV_8UC1);
    resized_alpha.copyTo(mask_(cv::Rect(margin, margin, w, h)));
    cv::dilate(mask_, region, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  }
  outline_ = templateEdgePoints(template_scan_, edge_threshold, edge_full_strength, kMinTemplateChain, region);
  if (outline_.size() < kMinTemplatePoints)
    throw MemoryError("prototype '" + label_ + "' is read as a grey template (not two grey levels) and has " +
                      std::to_string(outline_.size()) + " edge points at edge_threshold " +
                      std::to_string(edge_threshold) + " (at least " + std::to_string(kMinTemplatePoints) +
                      " needed): too little contrast, or too small");
  if (alpha.empty())
  {
    // The object is where its edges are: their convex hull, 2 px wider.
    std::vector<cv::Point2f> points;
    for (const OutlinePoint& o : outline_)
      points.push_back(o.position);
    std::vector<cv::Point2f> hull;
    cv::convexHull(points, hull);
    std::vector<cv::Point> polygon;
    for (const cv::Point2f& p : hull)
      polygon.emplace_back(cvRound(p.x), cvRound(p.y));
    mask_ = cv::Mat::zeros(padded.size(), CV_8UC1);
    cv::fillConvexPoly(mask_, polygon, cv::Scalar(255));
    cv::dilate(mask_, mask_, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  }
  return box;
}

cv::Mat Prototype::scanImage() const
{
  return isTemplate() ? template_scan_.clone() : prepareScanImage(mask_, blur_sigma_);
}

// Paper 4.4: every node holds its radial scan in every direction bin, made
// by the scanner the V-particles use, in the smoothed mask: with stride 1 a
// lookup equals a direct scan. Far from the outline the smoothed mask is
// flat, so each ray leaps over the free space a distance transform gives.
void Prototype::buildTable(int stride, double edge_threshold, double edge_full_strength)
{
  const cv::Mat scan_image = scanImage();
  table_ = RadialTable(mask_.size(), stride);
  if (isTemplate())
  {
    // A template's table holds what the camera's scanner finds: the same
    // thresholds, following the template's own contrast.
    table_.fill(RadialScanner(scan_image, EdgeThresholds(scan_image, edge_threshold, edge_full_strength),
                              RadialTable::kMaxDistance + 2.f),
                mask_.size());
    return;
  }
  cv::Mat inside_distance, outside_distance, inverted;
  cv::distanceTransform(mask_, inside_distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::bitwise_not(mask_, inverted);
  cv::distanceTransform(inverted, outside_distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  // Distance to the nearest pixel of the other class (one term is 0 everywhere).
  cv::Mat free_space = inside_distance + outside_distance;
  // A Gaussian of sigma leaves a grey step above the threshold only within
  // sigma * sqrt(2 ln(255 / threshold)) px of the outline; add 1 px for the
  // samples either side of a step, 0.71 px for rounding to the pixel and
  // 0.5 px from pixel centre to outline.
  const double reach = blur_sigma_ > 0 ? blur_sigma_ * std::sqrt(2.0 * std::log(std::max(1.0, 255.0 / edge_threshold))) : 0.0;
  free_space -= static_cast<float>(reach + 2.5);
  cv::max(free_space, 0.0, free_space);

  table_.fill(RadialScanner(scan_image, edge_threshold, RadialTable::kMaxDistance + 2.f, free_space), mask_.size());
}

void Prototype::buildOutline()
{
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask_.clone(), contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  outline_.clear();
  for (const auto& contour : contours)
  {
    const int n = static_cast<int>(contour.size());
    if (n < 8)
      continue;
    const int stride = std::max(1, static_cast<int>(kOutlineSpacing));
    for (int i = 0; i < n; i += stride)
    {
      const cv::Point2f prev = contour[(i - 3 + n) % n], next = contour[(i + 3) % n];
      cv::Point2f tangent = next - prev;
      const float len = std::hypot(tangent.x, tangent.y);
      if (len < 1e-3f)
        continue;
      tangent /= len;
      cv::Point2f normal(tangent.y, -tangent.x);
      // Orient outwards: the pixel 2 px along the normal must be background.
      const cv::Point2f p = contour[i];
      const cv::Point probe(cvRound(p.x + 2 * normal.x), cvRound(p.y + 2 * normal.y));
      const bool probe_inside = probe.x >= 0 && probe.y >= 0 && probe.x < mask_.cols && probe.y < mask_.rows &&
                                mask_.at<uchar>(probe) != 0;
      if (probe_inside)
        normal = -normal;
      // Contour pixels are the shape's last pixels: the edge lies half a pixel outwards.
      outline_.push_back({p + 0.5f * normal, normal});
    }
  }
}
}  // namespace amcr
