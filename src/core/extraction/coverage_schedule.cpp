#include "amcr/extraction/coverage_schedule.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
// Roberts' R2 sequence: the fractional parts of n / g and n / g^2, g the
// plastic number (the root of x^3 = x + 1).
constexpr double kPlastic = 1.32471795724474602596;
constexpr double kR2a = 1.0 / kPlastic;
constexpr double kR2b = 1.0 / (kPlastic * kPlastic);
constexpr double kGolden = 0.61803398874989484820;  // the heading's step per round, of a turn

double fraction(double x) { return x - std::floor(x); }

/// A polygon and its bounding box (the box rejects most places at once).
struct Skipped
{
  const std::vector<cv::Point2f>* polygon;
  cv::Rect2f box;
};

bool insideAny(const std::vector<Skipped>& skipped, const cv::Point2f& p)
{
  for (const Skipped& s : skipped)
    if (p.x >= s.box.x && p.y >= s.box.y && p.x <= s.box.x + s.box.width && p.y <= s.box.y + s.box.height &&
        cv::pointPolygonTest(*s.polygon, p, false) >= 0)
      return true;
  return false;
}
}  // namespace

double coverageSpacing(double min_object_size) { return std::max(kMinCoverageSpacing, min_object_size / 3.0); }

std::vector<RayPlace> coveragePlaces(cv::Size size, double spacing, int frames, std::int64_t frame,
                                     const std::vector<std::vector<cv::Point2f>>& skip)
{
  if (!(spacing >= 1.0))
    throw ParameterError("coveragePlaces: spacing " + std::to_string(spacing) + " px is below 1 px");
  if (frames < 1)
    throw ParameterError("coveragePlaces: coverage in " + std::to_string(frames) + " frames (at least 1)");
  std::vector<RayPlace> places;
  if (size.width <= 0 || size.height <= 0 || frame < 0)
    return places;
  const std::int64_t round = frame / frames;
  const int bucket = static_cast<int>(frame % frames);
  // The round's offset within a cell and turn of the rays.
  const double ox = fraction(0.5 + round * kR2a) * spacing, oy = fraction(0.5 + round * kR2b) * spacing;
  const float theta = static_cast<float>(2.0 * M_PI * (fraction(round * kGolden) - 0.5));
  std::vector<Skipped> skipped;
  for (const std::vector<cv::Point2f>& polygon : skip)
    if (polygon.size() >= 3)
      skipped.push_back({&polygon, cv::boundingRect(polygon)});
  const int columns = static_cast<int>(std::ceil(size.width / spacing)),
            rows = static_cast<int>(std::ceil(size.height / spacing));
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i)
    {
      // The cell's rank: the R2 value of its lattice coordinates (a rank-1
      // lattice, whose K buckets each spread over the whole image).
      if (static_cast<int>(fraction(0.5 + i * kR2a + j * kR2b) * frames) != bucket)
        continue;
      const cv::Point2f p(static_cast<float>(i * spacing + ox), static_cast<float>(j * spacing + oy));
      if (p.x >= size.width || p.y >= size.height || insideAny(skipped, p))
        continue;
      places.push_back({p.x, p.y, theta});
    }
  return places;
}
}  // namespace amcr
