// The heading proposal (heading_proposal.h): at a prototype pixel, the bin
// whose 8 table scans match a V-particle's scans up to scale.
#include <cmath>

#include <gtest/gtest.h>

#include "amcr/heading_proposal.h"
#include "amcr/prototype.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

/// The table's own scans at (x, y) and `bin`, scaled by `scale`, as a V-particle would see them.
amcr::RaySignature signatureAt(const amcr::Prototype& p, int x, int y, int bin, float scale)
{
  amcr::RaySignature s;
  for (int k = 0; k < amcr::kFeatureRays; ++k)
  {
    const float d = p.distance(x, y, (bin + k * amcr::kFeatureBinStep) % amcr::kDirectionBins);
    s.distance[k] = d > 0.f ? scale * d : 0.f;
  }
  return s;
}

/// Angular distance in bins, modulo a turn.
int binDistance(int a, int b)
{
  const int d = std::abs(a - b) % amcr::kDirectionBins;
  return std::min(d, amcr::kDirectionBins - d);
}

TEST(HeadingProposal, FindsTheBinOfAScaledCopyOfTheScans)
{
  const amcr::Prototype prototype("arrow", amcr_test::drawPrototype(ShapeId::kArrow), 128, 40.0, 1.0);
  int tried = 0, found = 0;
  for (std::size_t i = 0; i < prototype.interior().size(); i += 97)
  {
    const cv::Point at = prototype.interior()[i];
    for (int bin = 0; bin < amcr::kDirectionBins; bin += 7)
    {
      const amcr::RaySignature s = signatureAt(prototype, at.x, at.y, bin, 1.7f);
      if (s.valid_rays() < 8)
        continue;  // the proposal is only as sure as the scans are complete
      ++tried;
      // Within one bin (5 degrees): neighbouring bins can see the same edges.
      found += binDistance(amcr::bestHeadingBin(prototype, at.x, at.y, s), bin) <= 1 ? 1 : 0;
    }
  }
  ASSERT_GT(tried, 100);
  // A scaled copy of the scans must point back at their own bin in nearly all places;
  // near-symmetric places (inside the arrow's straight shaft) may match a turned copy.
  EXPECT_GE(found, 0.8 * tried) << found << " of " << tried;
}

TEST(HeadingProposal, NoSignatureNoProposal)
{
  const amcr::Prototype prototype("star", amcr_test::drawPrototype(ShapeId::kStar), 64, 40.0, 1.0);
  const cv::Point at = prototype.interior().front();
  amcr::RaySignature two_rays;
  two_rays.distance[0] = 5.f;
  two_rays.distance[3] = 7.f;
  EXPECT_EQ(amcr::bestHeadingBin(prototype, at.x, at.y, amcr::RaySignature()), -1);
  EXPECT_EQ(amcr::bestHeadingBin(prototype, at.x, at.y, two_rays), -1);
}
}  // namespace
