#include "amcr/extraction/covered_outline.h"

#include <algorithm>
#include <cmath>

namespace amcr
{
namespace
{
// The grey on either side of a point: the mean of samples this far beyond
// the tolerance along the normal, px (out of the edge's blur, short of the
// far side of a thin part).
constexpr double kSideDepths[] = {1.5, 2.5, 3.5};

/// The mean grey at `side` (+1 outside, -1 inside) of a mapped point; false
/// when a sample leaves the image.
bool sideGrey(const RadialScanner& scanner, const MappedPoint& p, double tolerance, int side, float& grey)
{
  float sum = 0.f;
  for (const double depth : kSideDepths)
  {
    const double t = side * (tolerance + depth);
    const float x = static_cast<float>(p.image.x + t * p.normal.x);
    const float y = static_cast<float>(p.image.y + t * p.normal.y);
    if (!scanner.contains(x, y))
      return false;
    sum += scanner.sample(x, y);
  }
  grey = sum / static_cast<float>(std::size(kSideDepths));
  return true;
}

float median(std::vector<float> values)
{
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

/// Clears the runs of set flags (cyclic, in outline order) shorter than `min_length`.
void dropShortRuns(std::vector<std::uint8_t>& flags, std::size_t min_length)
{
  const std::size_t n = flags.size();
  std::size_t start = 0;
  while (start < n && flags[start] != 0)
    ++start;
  if (start == n)
    return;  // all set: one run round the whole outline
  // From a clear point, each run once round the cycle.
  for (std::size_t step = 1; step <= n;)
  {
    const std::size_t i = (start + step) % n;
    if (flags[i] == 0)
    {
      ++step;
      continue;
    }
    std::size_t length = 0;
    while (step + length <= n && flags[(start + step + length) % n] != 0)
      ++length;
    if (length < min_length)
      for (std::size_t k = 0; k < length; ++k)
        flags[(start + step + k) % n] = 0;
    step += length;
  }
}
}  // namespace

std::vector<std::uint8_t> coveredPoints(const RadialScanner& scanner, const std::vector<MappedPoint>& mapped,
                                        const std::vector<std::uint8_t>& on_edge, double tolerance,
                                        const CoverRule& rule)
{
  std::vector<std::uint8_t> covered(mapped.size(), 0);
  if (mapped.empty() || on_edge.size() != mapped.size())
    return covered;
  // The grey on either side of every point, read once; `sides` says where both are in the image.
  std::vector<float> in(mapped.size(), 0.f), out(mapped.size(), 0.f);
  std::vector<std::uint8_t> sides(mapped.size(), 0);
  for (std::size_t i = 0; i < mapped.size(); ++i)
    sides[i] = sideGrey(scanner, mapped[i], tolerance, -1, in[i]) && sideGrey(scanner, mapped[i], tolerance, +1, out[i]);
  std::vector<float> inside, surround;
  double threshold = 0.0;
  for (std::size_t i = 0; i < mapped.size(); ++i)
  {
    if (on_edge[i] == 0 || sides[i] == 0)
      continue;
    inside.push_back(in[i]);
    surround.push_back(out[i]);
    threshold += scanner.threshold(static_cast<float>(mapped[i].image.x), static_cast<float>(mapped[i].image.y));
  }
  if (inside.empty() || static_cast<double>(inside.size()) < rule.min_on_edge * static_cast<double>(mapped.size()))
    return covered;
  threshold /= static_cast<double>(inside.size());
  const float object_inside = median(inside), object_surround = median(surround);
  const double contrast = std::abs(object_inside - object_surround);
  if (contrast < threshold)
    return covered;
  const double like = rule.like * contrast;
  for (std::size_t i = 0; i < mapped.size(); ++i)
  {
    if (sides[i] == 0)
      continue;
    const bool third_outside = std::abs(out[i] - object_surround) > like && std::abs(out[i] - object_inside) > like;
    if (on_edge[i] != 0)
      // The edge of an occluder's contour that runs along the outline: a
      // third surface beyond it. The object's own outline lies beneath.
      covered[i] = third_outside;
    else
      // One surface across the point, neither the object's nor its surround's.
      covered[i] = std::abs(in[i] - out[i]) <= like && std::abs(in[i] - object_inside) > like &&
                   std::abs(out[i] - object_surround) > like;
  }
  dropShortRuns(covered, static_cast<std::size_t>(std::ceil(rule.min_run * static_cast<double>(mapped.size()))));
  return covered;
}
}  // namespace amcr
