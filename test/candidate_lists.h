// Answers of proposal-index queries: two compared entry by entry, for the
// tests that hold two indexes (built and read back, one thread and many) to
// the same answers; and whether one holds a true place.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/proposal_index.h"

namespace amcr_test
{
/// The same candidates in the same order: prototype, place, heading and
/// descriptor distance.
inline void expectSameCandidates(const std::vector<amcr::ProposalCandidate>& a,
                                 const std::vector<amcr::ProposalCandidate>& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    EXPECT_EQ(a[i].prototype, b[i].prototype) << "candidate " << i;
    EXPECT_EQ(a[i].x, b[i].x) << "candidate " << i;
    EXPECT_EQ(a[i].y, b[i].y) << "candidate " << i;
    EXPECT_EQ(a[i].bin, b[i].bin) << "candidate " << i;
    EXPECT_EQ(a[i].distance, b[i].distance) << "candidate " << i;
  }
}

/// Angular distance in heading bins, modulo a turn.
inline int binDistance(int a, int b)
{
  const int d = std::abs(a - b) % amcr::kDirectionBins;
  return std::min(d, amcr::kDirectionBins - d);
}

/// Whether a candidate names prototype `p` within `radius` table px of
/// `at` and within `bins` of heading bin `bin`.
inline bool hits(const std::vector<amcr::ProposalCandidate>& candidates, int p, const cv::Point2d& at, int bin,
                 double radius, int bins)
{
  for (const amcr::ProposalCandidate& c : candidates)
    if (c.prototype == p && std::hypot(c.x - at.x, c.y - at.y) <= radius && binDistance(c.bin, bin) <= bins)
      return true;
  return false;
}
}  // namespace amcr_test
