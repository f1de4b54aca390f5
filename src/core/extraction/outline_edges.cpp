#include "amcr/extraction/outline_edges.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace amcr
{
namespace
{
constexpr std::size_t kPolaritySampleStep = 3;  // every third outline point tells the polarity

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

/// The sample index k (t = k / 2) of the nearest local maximum of the signed
/// step, or a value beyond the reach when there is none.
int nearestEdgeIndex(const NormalProfile& profile, double threshold, int sign)
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
  return best_k;
}

/// The edge threshold where the outline point lies (it follows the local contrast).
double localThreshold(const RadialScanner& scanner, const MappedPoint& p)
{
  return scanner.threshold(static_cast<float>(p.image.x), static_cast<float>(p.image.y));
}
}  // namespace

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
    mapped.push_back({q, applyAffine(table_to_image, q), {nx / len, ny / len}, prototype.polarity()});
  }
  return mapped;
}

bool nearestEdge(const RadialScanner& scanner, const MappedPoint& p, double search, int sign, double& offset)
{
  const NormalProfile profile(scanner, p, search);
  const int k = nearestEdgeIndex(profile, localThreshold(scanner, p), sign);
  offset = 0.5 * k;
  return std::abs(k) <= profile.reach();
}

bool nearestEdgeSubpixel(const RadialScanner& scanner, const MappedPoint& p, double search, int sign, double& offset)
{
  const NormalProfile profile(scanner, p, search);
  const int k = nearestEdgeIndex(profile, localThreshold(scanner, p), sign);
  if (std::abs(k) > profile.reach())
    return false;
  // Vertex of the parabola through (k - 1, k, k + 1): within half a sample of k.
  const double before = sign * profile.step(k - 1), at = sign * profile.step(k), after = sign * profile.step(k + 1);
  const double curvature = before - 2.0 * at + after;
  const double shift = curvature < 0.0 ? std::clamp(0.5 * (before - after) / curvature, -0.5, 0.5) : 0.0;
  offset = 0.5 * (k + shift);
  return true;
}

int dominantPolarity(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped, double search)
{
  if (!mapped.empty() && mapped.front().polarity != 0)
    return mapped.front().polarity;
  int rising = 0, falling = 0;
  for (std::size_t i = 0; i < mapped.size(); i += kPolaritySampleStep)
  {
    double offset = 0.0, step = 0.0;
    if (strongestEdge(NormalProfile(scanner, mapped[i], search), localThreshold(scanner, mapped[i]), offset, step))
      (step > 0 ? rising : falling)++;
  }
  return rising >= falling ? 1 : -1;
}
double mappedOutlineSupport(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                            std::size_t outline_points, double tolerance)
{
  if (mapped.empty() || outline_points == 0)
    return 0.0;
  const std::vector<std::uint8_t> on_edge = pointsOnEdges(scanner, mapped, tolerance);
  return static_cast<double>(std::count(on_edge.begin(), on_edge.end(), 1)) / static_cast<double>(outline_points);
}

std::vector<std::uint8_t> pointsOnEdges(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        double tolerance)
{
  std::vector<std::uint8_t> on_edge(mapped.size(), 0);
  if (mapped.empty())
    return on_edge;
  // A printed shape has one polarity all round: count edges of the majority's only.
  const int sign = dominantPolarity(scanner, mapped, tolerance);
  for (std::size_t i = 0; i < mapped.size(); ++i)
  {
    double offset = 0.0;
    on_edge[i] = nearestEdge(scanner, mapped[i], tolerance, sign, offset) ? 1 : 0;
  }
  return on_edge;
}

double passSearch(double search, int pass, int passes)
{
  constexpr double kSearchShrink = 2.0 / 3.0;
  constexpr double kMinSearch = 1.5;  // px
  return std::max(kMinSearch, search * (1.0 - kSearchShrink * pass / std::max(1, passes - 1)));
}

double clutterLimit(std::vector<double> residual)
{
  constexpr double kResidualFactor = 2.5;
  constexpr double kMinResidualLimit = 1.0;  // px
  std::nth_element(residual.begin(), residual.begin() + residual.size() / 2, residual.end());
  return std::max(kMinResidualLimit, kResidualFactor * residual[residual.size() / 2]);
}
}  // namespace amcr
