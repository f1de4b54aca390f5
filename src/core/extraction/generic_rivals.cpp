#include "amcr/extraction/generic_rivals.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace amcr
{
namespace
{
constexpr int kEllipseVertices = 96;  // the rival ellipse as a polygon: 0.1 % of a radius off at most
constexpr int kEllipseRefits = 6;     // refits on the points nearest the last fit
// The rival ellipse is the one that explains at least this share of the
// outline: a blob that follows it scores no more than this share anyway,
// whatever the rest (a stem, a handle) does.
constexpr double kEllipseShare = 0.8;
constexpr double kOuterOutline = 1.0;  // table px: outline points this near the outer contour are on it

/// The outline points on the mask's outer contour (the longest of its
/// external contours), where the rivals are fitted: the holes' outlines are
/// parts that tell the prototype from each of them.
std::vector<cv::Point2f> outerOutline(const Prototype& prototype)
{
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(prototype.mask().clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  const auto longest = std::max_element(contours.begin(), contours.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  std::vector<cv::Point2f> outer;
  if (longest == contours.end())
    return outer;
  for (const OutlinePoint& o : prototype.outline())
    if (std::abs(cv::pointPolygonTest(*longest, o.position, true)) <= kOuterOutline)
      outer.push_back(o.position);
  return outer;
}

std::vector<cv::Point2d> ellipsePolygon(const cv::RotatedRect& e)
{
  std::vector<cv::Point2d> polygon;
  const double angle = e.angle * CV_PI / 180.0, c = std::cos(angle), s = std::sin(angle);
  const double a = 0.5 * e.size.width, b = 0.5 * e.size.height;
  for (int k = 0; k < kEllipseVertices; ++k)
  {
    const double t = 2.0 * CV_PI * k / kEllipseVertices, x = a * std::cos(t), y = b * std::sin(t);
    polygon.emplace_back(e.center.x + c * x - s * y, e.center.y + s * x + c * y);
  }
  return polygon;
}

std::vector<cv::Point2f> asFloat(const std::vector<cv::Point2d>& points)
{
  return std::vector<cv::Point2f>(points.begin(), points.end());
}

bool validEllipse(const cv::RotatedRect& e)
{
  return std::isfinite(e.center.x) && std::isfinite(e.center.y) && std::isfinite(e.angle) && e.size.width > 0.f &&
         e.size.height > 0.f && std::isfinite(e.size.width) && std::isfinite(e.size.height);
}

/// The ellipse that most of the outline follows: fitted to all of it, then
/// again and again to the kEllipseShare of the points nearest the last fit
/// (trimmed least squares), so that a stem or a handle does not pull it:
/// it is the round blob the shape could be taken for.
bool robustEllipse(const std::vector<cv::Point2f>& outline, std::vector<cv::Point2d>& polygon)
{
  cv::RotatedRect ellipse = cv::fitEllipseDirect(outline);
  if (!validEllipse(ellipse))
    return false;
  const std::size_t keep = std::max<std::size_t>(5, static_cast<std::size_t>(kEllipseShare * outline.size()));
  for (int round = 0; round < kEllipseRefits && keep < outline.size(); ++round)
  {
    const std::vector<cv::Point2f> fitted = asFloat(ellipsePolygon(ellipse));
    std::vector<std::pair<double, std::size_t>> distance;
    for (std::size_t i = 0; i < outline.size(); ++i)
      distance.emplace_back(std::abs(cv::pointPolygonTest(fitted, outline[i], true)), i);
    std::nth_element(distance.begin(), distance.begin() + keep, distance.end());
    std::vector<cv::Point2f> nearest;
    for (std::size_t k = 0; k < keep; ++k)
      nearest.push_back(outline[distance[k].second]);
    const cv::RotatedRect refit = cv::fitEllipseDirect(nearest);
    if (!validEllipse(refit))
      break;
    ellipse = refit;
  }
  polygon = ellipsePolygon(ellipse);
  return true;
}

double lineDistance(const cv::Point2d& p, const cv::Point2d& a, const cv::Point2d& b)
{
  const cv::Point2d d = b - a;
  const double length = std::hypot(d.x, d.y);
  if (length < 1e-9)
    return std::hypot(p.x - a.x, p.y - a.y);
  return std::abs(d.x * (p.y - a.y) - d.y * (p.x - a.x)) / length;
}

/// How far each mapped outline point lies from the rival mapped into the image.
std::vector<double> distancesToRival(const std::vector<MappedPoint>& mapped, const GenericRival& rival,
                                     const Homography& table_to_image)
{
  std::vector<cv::Point2d> image;
  for (const cv::Point2d& q : rival.points)
    image.push_back(applyHomography(table_to_image, q));
  std::vector<double> distance;
  distance.reserve(mapped.size());
  if (rival.kind == GenericRival::Kind::kLinePair)
  {
    for (const MappedPoint& p : mapped)
      distance.push_back(std::min(lineDistance(p.image, image[0], image[1]), lineDistance(p.image, image[2], image[3])));
    return distance;
  }
  const std::vector<cv::Point2f> polygon = asFloat(image);
  for (const MappedPoint& p : mapped)
    distance.push_back(std::abs(cv::pointPolygonTest(polygon, cv::Point2f(p.image), true)));
  return distance;
}
}  // namespace

const char* rivalName(GenericRival::Kind kind)
{
  switch (kind)
  {
    case GenericRival::Kind::kEllipse:
      return "ellipse";
    case GenericRival::Kind::kConvexHull:
      return "convex hull";
    case GenericRival::Kind::kRectangle:
      return "rectangle";
    case GenericRival::Kind::kLinePair:
      return "pair of lines";
  }
  return "rival";
}

std::vector<GenericRival> genericRivals(const Prototype& prototype)
{
  std::vector<GenericRival> rivals;
  const std::vector<cv::Point2f> contour = outerOutline(prototype);
  if (contour.size() < 5)
    return rivals;
  GenericRival ellipse{GenericRival::Kind::kEllipse, {}};
  if (robustEllipse(contour, ellipse.points))
    rivals.push_back(std::move(ellipse));

  std::vector<cv::Point2f> hull;
  cv::convexHull(contour, hull);
  rivals.push_back({GenericRival::Kind::kConvexHull, std::vector<cv::Point2d>(hull.begin(), hull.end())});

  const cv::RotatedRect box = cv::minAreaRect(contour);
  cv::Point2f corner[4];
  box.points(corner);
  const std::vector<cv::Point2d> rectangle(corner, corner + 4);
  rivals.push_back({GenericRival::Kind::kRectangle, rectangle});
  // The longer sides: (0, 1) and (2, 3), or (1, 2) and (3, 0).
  const bool first_longer = cv::norm(rectangle[1] - rectangle[0]) >= cv::norm(rectangle[2] - rectangle[1]);
  GenericRival lines{GenericRival::Kind::kLinePair, {}};
  lines.points = first_longer ? std::vector<cv::Point2d>{rectangle[0], rectangle[1], rectangle[2], rectangle[3]}
                              : std::vector<cv::Point2d>{rectangle[1], rectangle[2], rectangle[3], rectangle[0]};
  rivals.push_back(std::move(lines));
  return rivals;
}

RivalVerdict verifyAgainstRivals(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                 const std::vector<GenericRival>& rivals, const Homography& table_to_image,
                                 double tolerance, double apart, int min_points,
                                 const std::vector<std::uint8_t>& covered)
{
  RivalVerdict verdict;
  if (mapped.empty())
    return verdict;
  const int sign = dominantPolarity(scanner, mapped, tolerance);
  // Whether each point finds its edge, looked up once for all rivals.
  std::vector<signed char> on_edge(mapped.size(), -1);
  for (const GenericRival& rival : rivals)
  {
    const std::vector<double> distance = distancesToRival(mapped, rival, table_to_image);
    int points = 0, found = 0, hidden = 0;
    for (std::size_t i = 0; i < mapped.size(); ++i)
    {
      if (!(distance[i] > apart))
        continue;
      if (i < covered.size() && covered[i] != 0)
      {
        ++hidden;
        continue;
      }
      ++points;
      if (on_edge[i] < 0)
      {
        double offset = 0.0;
        on_edge[i] = nearestEdge(scanner, mapped[i], tolerance, sign, offset) ? 1 : 0;
      }
      found += on_edge[i];
    }
    if (points + hidden < min_points)
      continue;
    // Covered more than visible: the rival explains what shows as well.
    if (points < min_points || points < hidden)
    {
      verdict.tested = true;
      verdict.hidden = true;
      if (points < min_points)
        continue;
    }
    const double support = static_cast<double>(found) / points;
    if (!verdict.tested || support < verdict.support)
    {
      verdict.support = support;
      verdict.points = points;
      verdict.rival = rival.kind;
      verdict.tested = true;
    }
  }
  return verdict;
}
}  // namespace amcr
