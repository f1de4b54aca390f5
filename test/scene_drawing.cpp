// The scenes of scene_drawing.h (clutter, objects, noise), the affines and the corner error, and the
// temporary directory; the shapes themselves are drawn in shape_drawing.cpp.
#include "scene_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace amcr_test
{
namespace
{
constexpr int kSupersampling = 4;  // per axis
constexpr int kFixedPointBits = 4; // sub-pixel bits passed to cv::fillPoly

double clampGrey(double v) { return std::min(255.0, std::max(0.0, v)); }

cv::Rect2d boundsOf(const std::vector<cv::Point2d>& pts)
{
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& p : pts)
  {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  return {x0, y0, x1 - x0, y1 - y0};
}

// A random distractor (not any memory shape) centred on `c` with radius `r`.
std::vector<cv::Point2d> randomShape(std::mt19937_64& gen, const cv::Point2d& c, double r)
{
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int kind = static_cast<int>(u01(gen) * 3.0);
  const double rot = u01(gen) * 2.0 * M_PI;
  std::vector<cv::Point2d> local;
  if (kind == 0)  // star-shaped blob with 5-9 vertices
  {
    const int n = 5 + static_cast<int>(u01(gen) * 5.0);
    for (int i = 0; i < n; ++i)
    {
      const double a = 2.0 * M_PI * (i + 0.8 * (u01(gen) - 0.5)) / n;
      const double rr = r * (0.45 + 0.55 * u01(gen));
      local.emplace_back(rr * std::cos(a), rr * std::sin(a));
    }
  }
  else if (kind == 1)  // ellipse
  {
    const double ry = r * (0.3 + 0.7 * u01(gen));
    for (int i = 0; i < 48; ++i)
    {
      const double a = 2.0 * M_PI * i / 48;
      local.emplace_back(r * std::cos(a), ry * std::sin(a));
    }
  }
  else  // box
  {
    const double h = r * (0.25 + 0.75 * u01(gen));
    local = {{-r, -h}, {r, -h}, {r, h}, {-r, h}};
  }
  std::vector<cv::Point2d> out;
  for (const auto& p : local)
    out.emplace_back(c.x + std::cos(rot) * p.x - std::sin(rot) * p.y, c.y + std::sin(rot) * p.x + std::cos(rot) * p.y);
  return out;
}
}  // namespace

void fillPolygon(cv::Mat& image, const std::vector<cv::Point2d>& polygon, double value, bool antialiased)
{
  CV_Assert(image.type() == CV_8UC1 && polygon.size() >= 3);
  const cv::Rect2d b = boundsOf(polygon);
  const cv::Rect roi = cv::Rect(static_cast<int>(std::floor(b.x)) - 2, static_cast<int>(std::floor(b.y)) - 2,
                                static_cast<int>(std::ceil(b.width)) + 5, static_cast<int>(std::ceil(b.height)) + 5) &
                       cv::Rect(0, 0, image.cols, image.rows);
  if (roi.area() == 0)
    return;
  const int s = antialiased ? kSupersampling : 1;
  const double fixed = 1 << kFixedPointBits;
  // Low-res pixel centre i covers high-res pixels s*i .. s*i+s-1, whose mean
  // centre is s*i + (s-1)/2.
  std::vector<cv::Point> pts;
  for (const auto& p : polygon)
    pts.emplace_back(static_cast<int>(std::lround(((p.x - roi.x) * s + (s - 1) / 2.0) * fixed)),
                     static_cast<int>(std::lround(((p.y - roi.y) * s + (s - 1) / 2.0) * fixed)));
  cv::Mat coverage(roi.height * s, roi.width * s, CV_8UC1, cv::Scalar(0));
  const std::vector<std::vector<cv::Point>> contours = {pts};
  cv::fillPoly(coverage, contours, cv::Scalar(255), cv::LINE_8, kFixedPointBits);
  cv::Mat alpha;
  if (s > 1)
    cv::resize(coverage, alpha, roi.size(), 0, 0, cv::INTER_AREA);
  else
    alpha = coverage;
  cv::Mat target = image(roi);
  for (int y = 0; y < roi.height; ++y)
    for (int x = 0; x < roi.width; ++x)
    {
      const double a = alpha.at<uchar>(y, x) / 255.0;
      uchar& px = target.at<uchar>(y, x);
      px = cv::saturate_cast<uchar>((1.0 - a) * px + a * value);
    }
}

std::vector<cv::Point2d> transformPoints(const amcr::Affine& a, const std::vector<cv::Point2d>& points)
{
  std::vector<cv::Point2d> out;
  out.reserve(points.size());
  for (const auto& p : points)
    out.push_back(amcr::applyAffine(a, p));
  return out;
}

amcr::Affine makeAffine(const cv::Point2d& prototype_centre, const cv::Point2d& image_centre, double rotation,
                        double scale_x, double scale_y, double shear)
{
  const cv::Matx22d r(std::cos(rotation), -std::sin(rotation), std::sin(rotation), std::cos(rotation));
  const cv::Matx22d sh(1.0, shear, 0.0, 1.0);
  const cv::Matx22d sc(scale_x, 0.0, 0.0, scale_y);
  const cv::Matx22d l = r * sh * sc;
  const cv::Vec2d t = cv::Vec2d(image_centre.x, image_centre.y) - l * cv::Vec2d(prototype_centre.x, prototype_centre.y);
  return amcr::Affine(l(0, 0), l(0, 1), t[0], l(1, 0), l(1, 1), t[1]);
}

cv::Point2d prototypeCentre() { return {(kPrototypeImageSize - 1) / 2.0, (kPrototypeImageSize - 1) / 2.0}; }

cv::Mat renderClean(const Scene& scene)
{
  cv::Mat image = renderBackground(scene);
  drawObjects(image, scene.objects);
  return image;
}

void drawObjects(cv::Mat& image, const std::vector<Placement>& objects)
{
  for (const Placement& p : objects)
    fillPolygon(image, transformPoints(p.prototype_to_image, shapePolygon(p.shape)), p.grey);
}

Clutter distractorClutter(std::uint64_t seed)
{
  Clutter clutter;
  clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  clutter.seed = seed;
  return clutter;
}

cv::Mat renderBackground(const Scene& scene)
{
  const Clutter& c = scene.clutter;
  std::mt19937_64 gen(c.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);

  // Background with a linear brightness gradient in a random direction.
  cv::Mat image(scene.size, CV_8UC1);
  const double dir = u01(gen) * 2.0 * M_PI;
  const double half_diag = 0.5 * std::hypot(scene.size.width, scene.size.height);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
    {
      const double along = (std::cos(dir) * (x - 0.5 * image.cols) + std::sin(dir) * (y - 0.5 * image.rows)) / half_diag;
      image.at<uchar>(y, x) = cv::saturate_cast<uchar>(clampGrey(c.background + 0.5 * c.gradient * along));
    }

  // Regions the distractor shapes keep away from.
  std::vector<cv::Rect2d> keep_out;
  for (const Placement& p : scene.objects)
  {
    cv::Rect2d b = boundsOf(transformPoints(p.prototype_to_image, shapePolygon(p.shape)));
    keep_out.emplace_back(b.x - c.keep_out, b.y - c.keep_out, b.width + 2 * c.keep_out, b.height + 2 * c.keep_out);
  }
  const auto free_place = [&](const std::vector<cv::Point2d>& poly) {
    const cv::Rect2d b = boundsOf(poly);
    if (b.x < 2 || b.y < 2 || b.x + b.width > scene.size.width - 3 || b.y + b.height > scene.size.height - 3)
      return false;
    for (const auto& k : keep_out)
      if ((b & k).area() > 0)
        return false;
    return true;
  };

  // One draw per statement: the order in which a call's arguments are evaluated is unspecified
  // (GCC's and clang's differ), and a scene must be the same whatever compiled it. The draws come
  // in the order GCC evaluated them, the last argument first: the scenes the tests were measured on.
  const auto place = [&]() {
    const double y = u01(gen) * scene.size.height;
    return cv::Point2d(u01(gen) * scene.size.width, y);
  };

  // Distractor shapes: random polygons, ellipses and boxes, then silhouettes.
  for (int i = 0; i < c.random_shapes; ++i)
  {
    for (int attempt = 0; attempt < 200; ++attempt)
    {
      const cv::Point2d centre = place();
      const double radius = 18.0 + 37.0 * u01(gen);
      const double grey = 20.0 + 110.0 * u01(gen);
      const std::vector<cv::Point2d> poly = randomShape(gen, centre, radius);
      if (!free_place(poly))
        continue;
      fillPolygon(image, poly, grey);
      break;
    }
  }
  for (ShapeId id : c.silhouettes)
  {
    for (int attempt = 0; attempt < 400; ++attempt)
    {
      const cv::Point2d centre = place();
      const double scale = 0.4 + 0.35 * u01(gen);
      const double shear = 0.4 * (u01(gen) - 0.5);
      const double scale_y = scale * (0.8 + 0.4 * u01(gen));
      const amcr::Affine a = makeAffine(prototypeCentre(), centre, u01(gen) * 2.0 * M_PI, scale, scale_y, shear);
      const double grey = 20.0 + 90.0 * u01(gen);
      const std::vector<cv::Point2d> poly = transformPoints(a, shapePolygon(id));
      if (!free_place(poly))
        continue;
      fillPolygon(image, poly, grey);
      break;
    }
  }

  // Lines anywhere; the objects are drawn over them.
  for (int i = 0; i < c.lines; ++i)
  {
    const cv::Point2d from = place();
    const cv::Point2d to = place();
    const cv::Point p0(static_cast<int>(from.x), static_cast<int>(from.y));  // truncated to whole px
    const cv::Point p1(static_cast<int>(to.x), static_cast<int>(to.y));
    const int thickness = 1 + static_cast<int>(u01(gen) * 3.0);
    const double grey = 20.0 + 110.0 * u01(gen);
    cv::line(image, p0, p1, cv::Scalar(grey), thickness, cv::LINE_AA);
  }
  return image;
}

cv::Mat addNoise(const cv::Mat& clean, double sigma, std::uint64_t seed)
{
  CV_Assert(clean.type() == CV_8UC1);
  if (sigma <= 0.0)
    return clean.clone();
  cv::Mat noise(clean.size(), CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat f;
  clean.convertTo(f, CV_32FC1);
  f += noise;
  cv::Mat out;
  f.convertTo(out, CV_8UC1);  // rounds and saturates
  return out;
}

std::vector<cv::Mat> renderSequence(const Scene& scene, int frames)
{
  const cv::Mat clean = renderClean(scene);
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k)
    out.push_back(addNoise(clean, scene.clutter.noise_sigma, scene.clutter.seed * 1000 + static_cast<std::uint64_t>(k)));
  return out;
}

std::vector<cv::Point2d> imageCorners(const cv::Size& size)
{
  const double w = size.width - 1.0, h = size.height - 1.0;
  return {{0.0, 0.0}, {w, 0.0}, {w, h}, {0.0, h}};
}

double cornerError(const amcr::Affine& reported, const amcr::Affine& truth, const cv::Size& prototype_size)
{
  double sum = 0.0;
  const std::vector<cv::Point2d> corners = imageCorners(prototype_size);
  for (const auto& c : corners)
  {
    const cv::Point2d d = amcr::applyAffine(reported, c) - amcr::applyAffine(truth, c);
    sum += std::hypot(d.x, d.y);
  }
  return sum / corners.size();
}

TempDir::TempDir()
{
  std::string pattern = (std::filesystem::temp_directory_path() / "amcr_test_XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (!mkdtemp(buffer.data()))
    throw std::runtime_error("cannot create a temporary directory from " + pattern);
  path_ = buffer.data();
}

TempDir::~TempDir()
{
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::string TempDir::file(const std::string& name) const { return path_ + "/" + name; }

amcr::RaySignature tableRays(const amcr::Prototype& prototype, int x, int y, int bin, float scale)
{
  amcr::RaySignature s;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
  {
    const float d = prototype.distance(x, y, (bin + k * amcr::kFeatureBinStep) % amcr::kDirectionBins);
    s.distance[k] = d > 0.f ? scale * d : 0.f;
  }
  return s;
}
std::vector<cv::Mat> printedOverClutter(const cv::Mat& silhouette, const amcr::Affine& truth, const Clutter& clutter,
                                        int frames)
{
  Scene scene;
  scene.clutter = clutter;
  scene.objects = {{ShapeId::kCrescent, truth}};  // only to keep the distractors off the print's place
  const cv::Mat background = renderBackground(scene);
  cv::Mat shape;
  cv::warpAffine(silhouette, shape, cv::Mat(truth), background.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  const cv::Mat clean = background - shape * (150.0 / 255.0);
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k)
    out.push_back(addNoise(clean, clutter.noise_sigma, clutter.seed * 1000 + static_cast<std::uint64_t>(k)));
  return out;
}
}  // namespace amcr_test
