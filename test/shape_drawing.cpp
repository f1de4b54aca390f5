// The drawn shapes of scene_drawing.h: the five memory silhouettes, their prototype images and
// memory, the birds, the wavy oval and the random spiky silhouettes.
#include "scene_drawing.h"

#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>

namespace amcr_test
{
namespace
{
std::vector<cv::Point2d> polarPolygon(const cv::Point2d& centre, const std::vector<double>& angles_deg,
                                      const std::vector<double>& radii)
{
  std::vector<cv::Point2d> out;
  for (std::size_t i = 0; i < angles_deg.size(); ++i)
  {
    const double a = angles_deg[i] * M_PI / 180.0;
    out.emplace_back(centre.x + radii[i] * std::cos(a), centre.y + radii[i] * std::sin(a));
  }
  return out;
}

// An ellipse minus a disc that is off the ellipse's axes: no symmetry left.
std::vector<cv::Point2d> crescentPolygon()
{
  const cv::Point2d ec(100.0, 104.0);
  const double rx = 90.0, ry = 70.0, tilt = 25.0 * M_PI / 180.0;
  const cv::Point2d dc(125.0, 72.0);
  const double dr = 60.0;
  const auto in_disc = [&](const cv::Point2d& p) { return std::hypot(p.x - dc.x, p.y - dc.y) < dr; };
  const auto in_ellipse = [&](const cv::Point2d& p) {
    const double x = p.x - ec.x, y = p.y - ec.y;
    const double u = std::cos(tilt) * x + std::sin(tilt) * y;
    const double v = -std::sin(tilt) * x + std::cos(tilt) * y;
    return (u * u) / (rx * rx) + (v * v) / (ry * ry) < 1.0;
  };
  const int n = 720;
  std::vector<cv::Point2d> outer(n), inner(n);
  for (int i = 0; i < n; ++i)
  {
    const double t = 2.0 * M_PI * i / n;
    const double u = rx * std::cos(t), v = ry * std::sin(t);
    outer[i] = {ec.x + std::cos(tilt) * u - std::sin(tilt) * v, ec.y + std::sin(tilt) * u + std::cos(tilt) * v};
    inner[i] = {dc.x + dr * std::cos(t), dc.y + dr * std::sin(t)};
  }
  // The run of the ellipse outside the disc, then the run of the circle inside
  // the ellipse, walked backwards: one simple closed outline.
  const auto run = [n](const std::vector<cv::Point2d>& pts, const std::function<bool(const cv::Point2d&)>& keep) {
    int start = -1;
    for (int i = 0; i < n; ++i)
      if (keep(pts[i]) && !keep(pts[(i + n - 1) % n]))
        start = i;
    if (start < 0)
      throw std::logic_error("crescent: the disc does not cut the ellipse");
    std::vector<cv::Point2d> out;
    for (int k = 0; k < n && keep(pts[(start + k) % n]); ++k)
      out.push_back(pts[(start + k) % n]);
    return out;
  };
  std::vector<cv::Point2d> poly = run(outer, [&](const cv::Point2d& p) { return !in_disc(p); });
  std::vector<cv::Point2d> bite = run(inner, in_ellipse);
  poly.insert(poly.end(), bite.rbegin(), bite.rend());
  return poly;
}
}  // namespace

const std::vector<ShapeId>& allShapes()
{
  static const std::vector<ShapeId> shapes = {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar, ShapeId::kEll,
                                              ShapeId::kFlag};
  return shapes;
}

std::string shapeName(ShapeId id)
{
  switch (id)
  {
    case ShapeId::kArrow:
      return "arrow";
    case ShapeId::kCrescent:
      return "crescent";
    case ShapeId::kStar:
      return "star";
    case ShapeId::kEll:
      return "ell";
    case ShapeId::kFlag:
      return "flag";
  }
  return "unknown";
}

std::vector<cv::Point2d> shapePolygon(ShapeId id)
{
  switch (id)
  {
    case ShapeId::kArrow:
      return {{15, 84}, {104, 84}, {92, 34}, {188, 96}, {124, 154}, {117, 121}, {15, 121}, {42, 103}};
    case ShapeId::kCrescent:
      return crescentPolygon();
    case ShapeId::kStar:
    {
      // Tips at uneven angles and radii, valleys at uneven depths.
      const std::vector<double> angles = {-92, -55, -18, 20, 52, 90, 128, 165, 205, 240};
      const std::vector<double> radii = {90, 36, 72, 30, 84, 42, 62, 33, 88, 40};
      return polarPolygon({100.0, 102.0}, angles, radii);
    }
    case ShapeId::kEll:
      return {{25, 15}, {62, 15}, {88, 42}, {88, 142}, {140, 142}, {168, 186}, {25, 186}};
    case ShapeId::kFlag:
      return {{30, 12}, {46, 12}, {46, 20}, {178, 46}, {46, 98}, {46, 188}, {30, 188}};
  }
  return {};
}

cv::Mat drawPrototype(ShapeId id, bool white_on_black, bool antialiased)
{
  cv::Mat image(kPrototypeImageSize, kPrototypeImageSize, CV_8UC1, cv::Scalar(white_on_black ? 0 : 255));
  fillPolygon(image, shapePolygon(id), white_on_black ? 255.0 : 0.0, antialiased);
  return image;
}

std::shared_ptr<const amcr::PrototypeMemory> drawnMemory(const std::vector<ShapeId>& shapes, const amcr::Params& params)
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (ShapeId id : shapes)
    memory->add(shapeName(id), drawPrototype(id), params);
  return memory;
}

std::shared_ptr<const amcr::PrototypeMemory> memoryWithApple()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> m = [] {
    auto memory = std::make_shared<amcr::PrototypeMemory>();
    for (const ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
      memory->add(shapeName(id), drawPrototype(id), amcr::Params());
    memory->add("apple", drawApple(true), amcr::Params());
    return memory;
  }();
  return m;
}

std::vector<cv::Point2d> drawnBird(bool crest)
{
  std::vector<cv::Point2d> polygon = {{15, 80},  {70, 100}, {90, 140}, {130, 150}, {155, 125},
                                      {160, 100}, {185, 95}, {170, 80}, {160, 62}, {140, 62},
                                      {130, 80},  {100, 90}, {60, 88}};
  if (crest)
    polygon.insert(polygon.begin() + 9, {{156, 40}, kCrestTip, {145, 42}});  // between (160, 62) and (140, 62)
  return polygon;
}

std::vector<cv::Point2d> wavyOval(cv::Point2d centre, double a, double b, double wave)
{
  std::vector<cv::Point2d> out;
  for (int k = 0; k < 720; ++k)
  {
    const double t = k * M_PI / 360.0;
    const cv::Point2d on(a * std::cos(t), b * std::sin(t));
    const double r = std::hypot(on.x, on.y);
    const double scale = (r + wave * std::sin(5.0 * t)) / r;
    out.emplace_back(centre.x + scale * on.x, centre.y + scale * on.y);
  }
  return out;
}

cv::Mat drawApple(bool stem)
{
  cv::Mat image = drawSilhouette(wavyOval(kAppleCentre, kAppleRadius, kAppleRadius, 0.0));
  if (stem)
    fillPolygon(image, {{96, 20}, {104, 20}, {104, 60}, {96, 60}}, 255.0);
  return image;
}

cv::Mat drawRandomSilhouette(std::uint64_t seed)
{
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  // Spiky: 12-18 vertices alternating outer and inner radii, unlike the
  // clutter's blobs of 5-9 vertices, ellipses and boxes (randomShape).
  const int n = 12 + 2 * static_cast<int>(u01(gen) * 4.0);
  const double r = 0.42 * kPrototypeImageSize;
  const cv::Point2d c = prototypeCentre();
  std::vector<cv::Point2d> polygon;
  for (int i = 0; i < n; ++i)
  {
    const double a = 2.0 * M_PI * (i + 0.5 * (u01(gen) - 0.5)) / n;
    const double rr = r * (i % 2 == 0 ? 0.7 + 0.3 * u01(gen) : 0.3 + 0.3 * u01(gen));
    polygon.emplace_back(c.x + rr * std::cos(a), c.y + rr * std::sin(a));
  }
  return drawSilhouette(polygon);
}

cv::Mat drawSilhouette(const std::vector<cv::Point2d>& polygon)
{
  cv::Mat image = cv::Mat::zeros(kPrototypeImageSize, kPrototypeImageSize, CV_8UC1);
  fillPolygon(image, polygon, 255.0);
  return image;
}
}  // namespace amcr_test
