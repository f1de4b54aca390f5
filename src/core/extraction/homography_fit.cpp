#include "amcr/extraction/homography_fit.h"

#include "amcr/extraction/outline_parts.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>

namespace amcr
{
namespace
{
// The search of each pass (passSearch) and the clutter left out of each
// refit (clutterLimit) are the affine refinement's, in outline_edges.h.
// A pass fits only when this many outline points found their edge: at least
// kMinFitPoints (twice the 4 a homography needs) and a kFitPointsDivisor-th of the outline.
constexpr std::size_t kMinFitPoints = 8;
constexpr std::size_t kFitPointsDivisor = 4;
// The passes stop once one moves no corner of the outline's box by kConverged
// px, after at least kMinPasses passes.
constexpr double kConverged = 0.05;
constexpr int kMinPasses = 3;

/// The largest distance between the points mapped by `a` and by `b`.
double largestMove(const Homography& a, const Homography& b, const std::vector<cv::Point2d>& points)
{
  double largest = 0.0;
  for (const cv::Point2d& p : points)
  {
    const cv::Point2d d = applyHomography(a, p) - applyHomography(b, p);
    largest = std::max(largest, std::isfinite(d.x) && std::isfinite(d.y) ? std::hypot(d.x, d.y) : HUGE_VAL);
  }
  return largest;
}

/// A least-squares homography (cv::findHomography, method 0: a linear
/// solution refined by Levenberg-Marquardt) of all pairs, refitted to the
/// pairs it maps within the residual limit (when it leaves any out). False
/// when a fit fails.
bool fitDroppingOutliers(const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& to, Homography& out)
{
  Homography first;
  const cv::Mat h = cv::findHomography(from, to, 0);
  if (h.empty() || !normalizeHomography(Homography(h), first))
    return false;
  std::vector<double> residual;
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    const cv::Point2d d = applyHomography(first, cv::Point2d(from[i])) - cv::Point2d(to[i]);
    residual.push_back(std::isfinite(d.x) && std::isfinite(d.y) ? std::hypot(d.x, d.y) : HUGE_VAL);
  }
  const double limit = clutterLimit(residual);
  std::vector<cv::Point2f> kept_from, kept_to;
  for (std::size_t i = 0; i < from.size(); ++i)
    if (residual[i] <= limit)
    {
      kept_from.push_back(from[i]);
      kept_to.push_back(to[i]);
    }
  if (kept_from.size() == from.size())
  {
    out = first;  // nothing to drop
    return true;
  }
  if (kept_from.size() < kMinFitPoints)
    return false;
  const cv::Mat refit = cv::findHomography(kept_from, kept_to, 0);
  return !refit.empty() && normalizeHomography(Homography(refit), out);
}

/// Signed area of a polygon (positive: counter-clockwise in x right, y up).
double signedArea(const std::vector<cv::Point2d>& polygon)
{
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
  {
    const cv::Point2d& a = polygon[i];
    const cv::Point2d& b = polygon[(i + 1) % polygon.size()];
    twice += a.x * b.y - b.x * a.y;
  }
  return 0.5 * twice;
}

/// Whether every turn of the polygon has the sign `orientation` (+1 / -1).
bool strictlyConvex(const std::vector<cv::Point2d>& polygon, int orientation)
{
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const cv::Point2d e1 = polygon[(i + 1) % n] - polygon[i];
    const cv::Point2d e2 = polygon[(i + 2) % n] - polygon[(i + 1) % n];
    if (!(orientation * (e1.x * e2.y - e1.y * e2.x) > 0.0))
      return false;
  }
  return true;
}
}  // namespace

/// The corners of the outline's bounding box, table px, in order around it.
std::vector<cv::Point2d> outlineBox(const Prototype& prototype)
{
  if (prototype.outline().empty())
    return {};
  double x0 = prototype.outline().front().position.x, x1 = x0;
  double y0 = prototype.outline().front().position.y, y1 = y0;
  for (const auto& o : prototype.outline())
  {
    x0 = std::min(x0, static_cast<double>(o.position.x));
    x1 = std::max(x1, static_cast<double>(o.position.x));
    y0 = std::min(y0, static_cast<double>(o.position.y));
    y1 = std::max(y1, static_cast<double>(o.position.y));
  }
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

std::vector<MappedPoint> mapOutline(const Prototype& prototype, const Homography& table_to_image)
{
  std::vector<MappedPoint> mapped;
  mapped.reserve(prototype.outline().size());
  for (const auto& o : prototype.outline())
  {
    const cv::Point2d q(o.position.x, o.position.y);
    cv::Matx22d j;
    if (!homographyJacobian(table_to_image, q, j))
      continue;
    // Normals map with the inverse transpose of the local linear map.
    const double det = j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0);
    if (std::abs(det) < 1e-12)
      continue;
    const double nx = (j(1, 1) * o.normal.x - j(1, 0) * o.normal.y) / det;
    const double ny = (-j(0, 1) * o.normal.x + j(0, 0) * o.normal.y) / det;
    const double len = std::hypot(nx, ny);
    const cv::Point2d image = applyHomography(table_to_image, q);
    if (len < 1e-12 || !std::isfinite(image.x) || !std::isfinite(image.y))
      continue;
    mapped.push_back({q, image, {nx / len, ny / len}, prototype.polarity()});
  }
  return mapped;
}

Homography refineHomographyOnEdges(const Prototype& prototype, const RadialScanner& scanner,
                                   const Homography& table_to_image, int iterations, double search)
{
  Homography current = table_to_image;
  if (iterations <= 0)
    return current;
  const int sign = dominantPolarity(scanner, mapOutline(prototype, current), search);
  const std::vector<cv::Point2d> box = outlineBox(prototype);
  for (int pass = 0; pass < iterations; ++pass)
  {
    // Coarse to fine: the search shrinks to a third over the passes (slowly:
    // a strong perspective needs the wide search for a few passes).
    const double range = passSearch(search, pass, iterations);
    const std::vector<MappedPoint> mapped = mapOutline(prototype, current);
    std::vector<cv::Point2f> from, to;
    for (const auto& p : mapped)
    {
      double offset = 0.0;
      if (!nearestEdgeSubpixel(scanner, p, range, sign, offset))
        continue;
      from.emplace_back(p.table);
      to.emplace_back(p.image + offset * p.normal);
    }
    if (from.size() < std::max(kMinFitPoints, prototype.outline().size() / kFitPointsDivisor))
      break;
    // Least squares on every edge found, then again without the points that
    // fit that homography worst (clutter): the offsets themselves say
    // nothing here, since a perspective the start lacks shows as large
    // offsets at the far and near ends of the outline.
    Homography next;
    if (!fitDroppingOutliers(from, to, next))
      break;
    const double moved = largestMove(current, next, box);
    current = next;
    if (pass >= kMinPasses && moved < kConverged)
      break;
  }
  return current;
}

double outlineSupport(const Prototype& prototype, const RadialScanner& scanner, const Homography& table_to_image,
                      double tolerance, double part_shift)
{
  return verifyOutline(prototype, scanner, table_to_image, tolerance, part_shift, false).score;
}

OutlineVerification verifyOutline(const Prototype& prototype, const RadialScanner& scanner,
                                  const Homography& table_to_image, double tolerance, double part_shift,
                                  bool find_covered)
{
  std::vector<MappedPoint> mapped = mapOutline(prototype, table_to_image);
  fitPartsWithinShare(prototype, scanner, mapped, part_shift, tolerance);
  return verifyMappedOutline(scanner, mapped, prototype.outline().size(), tolerance,
                             find_covered && !prototype.isTemplate());
}

double outlineResidual(const Prototype& prototype, const RadialScanner& scanner, const Homography& table_to_image,
                       double cap)
{
  const std::vector<MappedPoint> mapped = mapOutline(prototype, table_to_image);
  if (prototype.outline().empty())
    return cap;
  const int sign = mapped.empty() ? 1 : dominantPolarity(scanner, mapped, cap);
  double sum = cap * static_cast<double>(prototype.outline().size() - mapped.size());
  for (const auto& p : mapped)
  {
    double offset = 0.0;
    sum += nearestEdgeSubpixel(scanner, p, cap, sign, offset) ? std::min(cap, std::abs(offset)) : cap;
  }
  return sum / static_cast<double>(prototype.outline().size());
}

bool homographyWellConditioned(const Homography& table_to_image, const std::vector<cv::Point2d>& region,
                               double max_scale, double max_depth_ratio, std::string* why)
{
  const auto fail = [why](const std::string& reason) {
    if (why)
      *why = reason;
    return false;
  };
  if (region.size() < 3)
    return fail("the region has fewer than 3 vertices");
  const double area = signedArea(region);
  if (area == 0.0)
    return fail("the region has no area");
  const int orientation = area > 0.0 ? 1 : -1;
  double min_w = 0.0, max_w = 0.0;
  std::vector<cv::Point2d> mapped;
  for (std::size_t i = 0; i < region.size(); ++i)
  {
    const cv::Point2d& q = region[i];
    const double w = table_to_image(2, 0) * q.x + table_to_image(2, 1) * q.y + table_to_image(2, 2);
    cv::Matx22d j;
    if (!std::isfinite(w) || !(w > 0.0) || !homographyJacobian(table_to_image, q, j))
      return fail("a vertex maps to or beyond the horizon (w <= 0)");
    min_w = i == 0 ? w : std::min(min_w, w);
    max_w = i == 0 ? w : std::max(max_w, w);
    if (j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0) <= 0.0)
      return fail("the homography mirrors or collapses the region");
    double smallest = 0.0, largest = 0.0;
    affineScales(Affine(j(0, 0), j(0, 1), 0.0, j(1, 0), j(1, 1), 0.0), smallest, largest);
    if (!(largest <= max_scale) || !(smallest >= 1.0 / max_scale))
      return fail("a local scale leaves [1 / max_scale, max_scale]");
    mapped.push_back(applyHomography(table_to_image, q));
  }
  if (max_w > max_depth_ratio * min_w)
    return fail("the perspective is too strong (depth ratio above the bound)");
  if (!strictlyConvex(mapped, orientation))
    return fail("the mapped region is not convex");
  return true;
}
}  // namespace amcr
