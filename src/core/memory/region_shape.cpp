#include "amcr/memory/region_shape.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace amcr
{
namespace
{
constexpr int kFillShift = 4;  // fractional bits of the region's corners in cv::fillPoly
constexpr int kMaxLineContact = 4 * kLineCutSize;  // border px a shape crossed by lines may touch

/// Area of a polygon, px^2 (whatever its orientation).
double area(const std::vector<cv::Point2d>& polygon)
{
  std::vector<cv::Point2f> points(polygon.begin(), polygon.end());
  return std::abs(cv::contourArea(points));
}

/// The part of `polygon` on the side of the line x (axis 0) or y (axis 1) =
/// `limit` that `keep_below` names (Sutherland-Hodgman, one edge).
std::vector<cv::Point2d> clipAxis(const std::vector<cv::Point2d>& polygon, int axis, double limit, bool keep_below)
{
  std::vector<cv::Point2d> out;
  const auto coord = [axis](const cv::Point2d& p) { return axis == 0 ? p.x : p.y; };
  const auto inside = [&](const cv::Point2d& p) { return keep_below ? coord(p) <= limit : coord(p) >= limit; };
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const cv::Point2d& p = polygon[i];
    const cv::Point2d& q = polygon[(i + 1) % polygon.size()];
    const bool p_in = inside(p), q_in = inside(q);
    if (p_in)
      out.push_back(p);
    if (p_in != q_in)
    {
      const double t = (limit - coord(p)) / (coord(q) - coord(p));
      out.push_back(p + t * (q - p));
    }
  }
  return out;
}

/// `polygon` clipped to the pixels of an image of `size` (pixel-centre
/// convention: the image covers [-0.5, w - 0.5] x [-0.5, h - 0.5]).
std::vector<cv::Point2d> clipToImage(std::vector<cv::Point2d> polygon, const cv::Size& size)
{
  polygon = clipAxis(polygon, 0, -0.5, false);
  polygon = clipAxis(polygon, 0, size.width - 0.5, true);
  polygon = clipAxis(polygon, 1, -0.5, false);
  polygon = clipAxis(polygon, 1, size.height - 0.5, true);
  return polygon;
}

CutShape failure(const std::string& why)
{
  CutShape cut;
  cut.why = why;
  return cut;
}

/// The shape when a line (a cable, a table edge) crosses it: its edges join
/// the outline to the region's border, so no outline stays clear of it. The
/// pixels free of edges that connect to the border are outside, with the
/// edges widened by the opening's reach first: where the line meets the
/// shape, the outline has a gap as wide as the line (a dark line over a dark
/// shape steps nowhere), and the strip between the line's edges would lead
/// the outside in. What the outside (grown back) leaves is the shape with
/// the line's stubs, which an opening of kLineCutSize px removes. The part of
/// the opened mask (8-connected) that touches the border at most where a
/// stub or two may (kMaxLineContact px) with the largest area
/// of at least `least_area` is grown back within the opening's reach, to give
/// back the corners the opening rounded. Its outer contour, or none (empty)
/// when no part qualifies.
std::vector<cv::Point> shapeCrossedByLines(const cv::Mat& closed, const cv::Mat& inner, const cv::Mat& border,
                                           double least_area)
{
  const cv::Mat cut_lines = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kLineCutSize, kLineCutSize));
  cv::Mat widened;
  cv::dilate(closed, widened, cut_lines);
  cv::Mat parts;
  const int count = cv::connectedComponents(inner & ~widened, parts, 4, CV_32S);
  std::vector<uchar> outside_part(static_cast<std::size_t>(count), 0);
  for (int y = 0; y < parts.rows; ++y)
    for (int x = 0; x < parts.cols; ++x)
      if (border.at<uchar>(y, x) && parts.at<int>(y, x) > 0)
        outside_part[static_cast<std::size_t>(parts.at<int>(y, x))] = 255;
  cv::Mat outside(parts.size(), CV_8UC1);
  for (int y = 0; y < parts.rows; ++y)
    for (int x = 0; x < parts.cols; ++x)
      outside.at<uchar>(y, x) = outside_part[static_cast<std::size_t>(parts.at<int>(y, x))];
  cv::dilate(outside, outside, cut_lines);
  const cv::Mat shape = inner & ~outside;
  cv::Mat opened;
  cv::morphologyEx(shape, opened, cv::MORPH_OPEN, cut_lines, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat pieces, stats, centroids;
  const int pieces_count = cv::connectedComponentsWithStats(opened, pieces, stats, centroids, 8, CV_32S);
  int best = -1;
  double best_area = least_area;
  for (int i = 1; i < pieces_count; ++i)
  {
    const double piece_area = stats.at<int>(i, cv::CC_STAT_AREA);
    // A line's stub may still reach the border where the shape comes close
    // to it; a shape the region cuts through meets the border along more.
    if (piece_area < best_area || cv::countNonZero((pieces == i) & border) > kMaxLineContact)
      continue;
    best = i;
    best_area = piece_area;
  }
  if (best < 0)
    return {};
  cv::Mat grown;
  cv::dilate(pieces == best, grown, cut_lines);
  grown &= shape;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(grown, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  const auto largest = std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
  return largest == contours.end() ? std::vector<cv::Point>() : *largest;
}

CutShape outsideImage(const cv::Size& size)
{
  return failure("the region lies outside the image (" + std::to_string(size.width) + " x " +
                 std::to_string(size.height) + " px)");
}

/// The image's grey levels over `bounds` (its border repeated where the box
/// reaches past it) with `alpha` as the alpha channel, CV_8UC4.
cv::Mat greyTemplate(const cv::Mat& image, const cv::Rect& bounds, const cv::Mat& alpha)
{
  const cv::Rect inside = bounds & cv::Rect(cv::Point(), image.size());
  cv::Mat grey, padded;
  if (image.channels() == 3)
    cv::cvtColor(image(inside), grey, cv::COLOR_BGR2GRAY);
  else
    grey = image(inside);
  cv::copyMakeBorder(grey, padded, inside.y - bounds.y, bounds.br().y - inside.br().y, inside.x - bounds.x,
                     bounds.br().x - inside.br().x, cv::BORDER_REPLICATE);
  cv::Mat bgra;
  cv::merge(std::vector<cv::Mat>{padded, padded, padded, alpha}, bgra);
  return bgra;
}
}  // namespace

std::vector<cv::Point2f> rectangleRegion(double x, double y, double width, double height)
{
  const auto p = [](double px, double py) { return cv::Point2f(static_cast<float>(px), static_cast<float>(py)); };
  return {p(x, y), p(x + width, y), p(x + width, y + height), p(x, y + height)};
}

CutShape cutShape(const cv::Mat& image, const std::vector<cv::Point2f>& region, const EdgeParams& params)
{
  // The region.
  if (region.size() < 3)
    return failure("the region is empty: it has " + std::to_string(region.size()) +
                   " points, a polygon needs at least 3 points");
  std::vector<cv::Point2d> polygon;
  for (std::size_t i = 0; i < region.size(); ++i)
  {
    if (!std::isfinite(region[i].x) || !std::isfinite(region[i].y))
      return failure("the region is empty: its point " + std::to_string(i) + " is not finite");
    polygon.emplace_back(region[i].x, region[i].y);
  }
  if (area(polygon) < 0.5)
    return failure("the region is empty: its polygon has zero area");

  // The image.
  if (image.empty())
    return failure("the image is empty");
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3)
    return failure("the image has type " + cv::typeToString(image.type()) +
                   "; only 8-bit grey (CV_8UC1) and BGR (CV_8UC3) images are taken");

  // The region's mask, clipped to the image, and its inset part.
  polygon = clipToImage(polygon, image.size());
  if (polygon.size() < 3 || area(polygon) < 0.5)
    return outsideImage(image.size());
  std::vector<cv::Point> corners;
  for (const cv::Point2d& p : polygon)
    corners.emplace_back(cvRound(p.x * (1 << kFillShift)), cvRound(p.y * (1 << kFillShift)));
  cv::Mat full_mask = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::fillPoly(full_mask, std::vector<std::vector<cv::Point>>{corners}, cv::Scalar(255), cv::LINE_8, kFillShift);
  const cv::Rect box = cv::boundingRect(full_mask);
  if (box.area() == 0)
    return outsideImage(image.size());
  // Everything below works in `roi`: the region's box, with room for the smoothing.
  const int pad = kRegionInset + 2 + static_cast<int>(std::ceil(3.0 * std::max(0.0, params.blur_sigma)));
  const cv::Rect roi = (box + cv::Size(2 * pad, 2 * pad) - cv::Point(pad, pad)) & cv::Rect(cv::Point(), image.size());
  const cv::Mat mask = full_mask(roi);
  const double region_area = cv::countNonZero(mask);
  cv::Mat inner;
  cv::erode(mask, inner,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kRegionInset + 1, 2 * kRegionInset + 1)),
            cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  if (cv::countNonZero(inner) == 0)
    return failure("the region is too small: nothing of it lies " + std::to_string(kRegionInset) +
                   " px inside its border");

  // Edges inside the region.
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image(roi), grey, cv::COLOR_BGR2GRAY);
  else
    grey = image(roi).clone();
  if (params.blur_sigma > 0.0)
    cv::GaussianBlur(grey, grey, cv::Size(0, 0), params.blur_sigma);
  // Canny's L2 Sobel magnitude is 4 times a step's grey-level change over 2 px.
  const double step = std::max(1.0, params.edge_threshold);
  cv::Mat edges;
  cv::Canny(grey, edges, 2.0 * step, 4.0 * step, 3, true);
  edges &= inner;
  if (cv::countNonZero(edges) == 0)
    return failure("no edges inside the region: nothing in it steps by edge_threshold = " + formatNumber(step) +
                   " grey levels");

  // Gaps closed; the outer contours are the candidates.
  cv::Mat closed;
  cv::morphologyEx(edges, closed, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(kClosingSize, kClosingSize)),
                   cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  closed &= inner;
  cv::Mat border;  // the inset region's outermost pixels
  cv::erode(inner, border, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  border = inner & ~border;
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(closed.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);

  const double least_area = std::max(kMinShapeArea, kMinRegionShare * region_area);
  int best = -1;
  double best_area = 0.0;
  cv::Mat fill(closed.size(), CV_8UC1);
  for (std::size_t i = 0; i < contours.size(); ++i)
  {
    const bool touches = std::any_of(contours[i].begin(), contours[i].end(),
                                     [&](const cv::Point& p) { return border.at<uchar>(p) != 0; });
    if (touches)
      continue;
    fill.setTo(0);
    cv::drawContours(fill, contours, static_cast<int>(i), cv::Scalar(255), cv::FILLED);
    const double interior = cv::countNonZero(fill & ~closed);
    if (interior >= least_area && interior > best_area)
    {
      best = static_cast<int>(i);
      best_area = interior;
    }
  }
  if (best < 0)
  {
    std::vector<cv::Point> crossed = shapeCrossedByLines(closed, inner, border, least_area);
    if (crossed.empty())
      return failure("no closed outline inside the region: none of its " + std::to_string(contours.size()) +
                     " edge contours stays clear of the region's border and encloses at least " +
                     formatNumber(std::round(least_area)) + " px, even with the lines that reach the border cut off");
    contours = {std::move(crossed)};
    best = 0;
  }

  // The silhouette: the filled outline, cropped with a margin.
  fill.setTo(0);
  cv::drawContours(fill, contours, best, cv::Scalar(255), cv::FILLED);
  const cv::Rect shape_box = cv::boundingRect(contours[best]);
  CutShape cut;
  cut.bounds = cv::Rect(shape_box.x + roi.x - kSilhouetteMargin, shape_box.y + roi.y - kSilhouetteMargin,
                        shape_box.width + 2 * kSilhouetteMargin, shape_box.height + 2 * kSilhouetteMargin);
  cut.silhouette = cv::Mat::zeros(cut.bounds.size(), CV_8UC1);
  fill(shape_box).copyTo(
      cut.silhouette(cv::Rect(kSilhouetteMargin, kSilhouetteMargin, shape_box.width, shape_box.height)));

  // Edges of the shape's own, off its outline: taught as a grey template too.
  cv::Mat inside;
  cv::erode(fill, inside,
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kInnerEdgeInset + 1, 2 * kInnerEdgeInset + 1)));
  if (cv::countNonZero(edges & inside) >= kMinInnerEdgePixels)
    cut.grey_template = greyTemplate(image, cut.bounds, cut.silhouette);
  return cut;
}
}  // namespace amcr
