// Two answers of proposal-index queries compared entry by entry, for the
// tests that hold two indexes (built and read back, one thread and many) to
// the same answers.
#pragma once

#include <vector>

#include <gtest/gtest.h>

#include "amcr/proposal_index.h"

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
}  // namespace amcr_test
