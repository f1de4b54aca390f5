#include "amcr/outline_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace amcr
{
namespace
{
// refineOnEdges: the search along the normals shrinks over the passes by
// this share of params.refine_search (coarse to fine), never below a floor.
constexpr double kSearchShrink = 2.0 / 3.0;
constexpr double kMinSearch = 1.5;  // px
// A pass fits only when this many outline points found their edge: at least
// kMinFitPoints and a kFitPointsDivisor-th of the outline.
constexpr std::size_t kMinFitPoints = 6;
constexpr std::size_t kFitPointsDivisor = 4;
// Points whose edge lies beyond kResidualFactor times the median offset
// (and beyond kMinResidualLimit px) are clutter and left out of the fit.
constexpr double kResidualFactor = 2.5;
constexpr double kMinResidualLimit = 1.0;  // px
constexpr std::size_t kPolaritySampleStep = 3;  // every third outline point tells the polarity

/// An outline point mapped into the image with its image-space unit normal.
struct MappedPoint
{
  cv::Point2d table;
  cv::Point2d image;
  cv::Point2d normal;
};

std::vector<MappedPoint> mapOutline(const Prototype& prototype, const Affine& table_to_image)
{
  // Normals map with the inverse transpose of the linear part.
  const double a = table_to_image(0, 0), b = table_to_image(0, 1);
  const double c = table_to_image(1, 0), d = table_to_image(1, 1);
  const double det = a * d - b * c;
  std::vector<MappedPoint> mapped;
  if (std::abs(det) < 1e-12)
    return mapped;
  mapped.reserve(prototype.outline().size());
  for (const auto& o : prototype.outline())
  {
    const cv::Point2d q(o.position.x, o.position.y);
    const double nx = (d * o.normal.x - c * o.normal.y) / det;
    const double ny = (-b * o.normal.x + a * o.normal.y) / det;
    const double len = std::hypot(nx, ny);
    if (len < 1e-12)
      continue;
    mapped.push_back({q, applyAffine(table_to_image, q), {nx / len, ny / len}});
  }
  return mapped;
}

/// Grey levels along an outline point's normal, every 0.5 px, enough to
/// evaluate the step I(t + 1) - I(t - 1) for |t| <= search + 0.5.
class NormalProfile
{
public:
  NormalProfile(const RadialScanner& scanner, const MappedPoint& p, double search)
    : reach_(std::min(kMaxReach, static_cast<int>(std::ceil(2.0 * search)))), half_(reach_ + 3)
  {
    for (int k = -half_; k <= half_; ++k)
    {
      const float x = static_cast<float>(p.image.x + 0.5 * k * p.normal.x);
      const float y = static_cast<float>(p.image.y + 0.5 * k * p.normal.y);
      grey_[k + half_] = scanner.contains(x, y) ? scanner.sample(x, y) : kOutside;
    }
  }

  /// Steps are searched at t = k / 2 for |k| <= reach().
  int reach() const { return reach_; }

  /// Signed step I(t + 1) - I(t - 1) at t = k / 2; 0 where a sample leaves the image.
  float step(int k) const
  {
    const float after = grey_[k + 2 + half_], before = grey_[k - 2 + half_];
    return (after == kOutside || before == kOutside) ? 0.f : after - before;
  }

private:
  static constexpr float kOutside = -1.f;
  static constexpr int kMaxReach = 200;  // 100 px, the largest refine_search
  int reach_;
  int half_;
  std::array<float, 2 * (kMaxReach + 3) + 1> grey_;  // on the stack: one profile per outline point and pass
};

/// The strongest step within the profile's reach; returns false when none
/// reaches the scanner's threshold.
bool strongestEdge(const NormalProfile& profile, double threshold, double& offset, double& step)
{
  float best = 0.f;
  int best_k = 0;
  for (int k = -profile.reach(); k <= profile.reach(); ++k)
  {
    const float s = profile.step(k);
    if (std::abs(s) > std::abs(best) || (std::abs(s) == std::abs(best) && std::abs(k) < std::abs(best_k)))
    {
      best = s;
      best_k = k;
    }
  }
  offset = 0.5 * best_k;
  step = best;
  return std::abs(best) >= threshold;
}

/// The nearest edge of polarity `sign` (+1: grey rises outwards, -1: falls)
/// within the profile's reach: the local maximum of the signed step closest
/// to the outline point (the "moving edges" search of model-based trackers).
/// Returns false when there is none.
bool nearestEdge(const NormalProfile& profile, double threshold, int sign, double& offset)
{
  int best_k = profile.reach() + 1;
  float prev = sign * profile.step(-profile.reach() - 1);
  float current = sign * profile.step(-profile.reach());
  for (int k = -profile.reach(); k <= profile.reach(); ++k)
  {
    const float next = sign * profile.step(k + 1);
    if (current >= threshold && current >= prev && current >= next && std::abs(k) < std::abs(best_k))
      best_k = k;
    prev = current;
    current = next;
  }
  offset = 0.5 * best_k;
  return std::abs(best_k) <= profile.reach();
}

/// The polarity most outline points show: +1 when the grey level rises
/// outwards (a dark print on light paper), -1 otherwise. Every
/// kPolaritySampleStep-th point is enough to tell.
int dominantPolarity(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped, double search)
{
  int rising = 0, falling = 0;
  for (std::size_t i = 0; i < mapped.size(); i += kPolaritySampleStep)
  {
    double offset = 0.0, step = 0.0;
    if (strongestEdge(NormalProfile(scanner, mapped[i], search), scanner.threshold(), offset, step))
      (step > 0 ? rising : falling)++;
  }
  return rising >= falling ? 1 : -1;
}
}  // namespace

Affine refineOnEdges(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                     int iterations, double search)
{
  Affine current = table_to_image;
  if (iterations <= 0)
    return current;
  const int sign = dominantPolarity(scanner, mapOutline(prototype, current), search);
  for (int pass = 0; pass < iterations; ++pass)
  {
    // Coarse to fine: the search shrinks to a third over the passes.
    const double range = std::max(kMinSearch, search * (1.0 - kSearchShrink * pass / std::max(1, iterations - 1)));
    const std::vector<MappedPoint> mapped = mapOutline(prototype, current);
    std::vector<cv::Point2d> from, to;
    std::vector<double> residual;
    for (const auto& p : mapped)
    {
      double offset = 0.0;
      if (!nearestEdge(NormalProfile(scanner, p, range), scanner.threshold(), sign, offset))
        continue;
      from.push_back(p.table);
      to.push_back(p.image + offset * p.normal);
      residual.push_back(std::abs(offset));
    }
    if (from.size() < std::max(kMinFitPoints, mapped.size() / kFitPointsDivisor))
      break;
    // Drop points whose edge is far beyond the typical one (clutter).
    std::vector<double> sorted = residual;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double limit = std::max(kMinResidualLimit, kResidualFactor * sorted[sorted.size() / 2]);
    std::vector<cv::Point2d> kept_from, kept_to;
    for (std::size_t i = 0; i < from.size(); ++i)
      if (residual[i] <= limit)
      {
        kept_from.push_back(from[i]);
        kept_to.push_back(to[i]);
      }
    Affine next;
    if (!fitAffine(kept_from, kept_to, next))
      break;
    current = next;
  }
  return current;
}

double outlineSupport(const Prototype& prototype, const RadialScanner& scanner, const Affine& table_to_image,
                      double tolerance)
{
  const std::vector<MappedPoint> mapped = mapOutline(prototype, table_to_image);
  if (mapped.empty() || prototype.outline().empty())
    return 0.0;
  // A printed shape has one polarity all round: count edges of the majority's only.
  const int sign = dominantPolarity(scanner, mapped, tolerance);
  int found = 0;
  for (const auto& p : mapped)
  {
    double offset = 0.0;
    found += nearestEdge(NormalProfile(scanner, p, tolerance), scanner.threshold(), sign, offset) ? 1 : 0;
  }
  return static_cast<double>(found) / static_cast<double>(prototype.outline().size());
}

double outlineSize(const std::vector<cv::Point2d>& outline)
{
  if (outline.size() < 2)
    return 0.0;
  const std::vector<cv::Point2f> points(outline.begin(), outline.end());
  const cv::RotatedRect box = cv::minAreaRect(points);
  return std::max(box.size.width, box.size.height);
}
}  // namespace amcr
