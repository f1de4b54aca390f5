// Poses proposed by the image itself (the paper's "feature feedback"): the
// 8 feature rays read at a place of the image are looked up in the memory's
// proposal index (proposal_index.h), and each place of the memory they
// match -- a prototype, a point of it, a heading bin and a scale -- is a
// similarity pose of that prototype in the image. Places on one object agree
// on its pose; the votes are pooled by prototype and pose, and the pools
// with the most places are where the result extraction fits first
// (fit_starts.cpp). Unlike the densest or the likeliest M-cluster, a vote
// needs no M-particle to have survived near the truth: with many prototypes
// in memory the index still ranks the true place among its first answers
// (a template cut from a real frame beside 16 others: first in 28% of the
// frames, among the first ten in 61%), while eq. 5 spreads the M-particles.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// One pool of agreeing votes.
struct PoseVote
{
  int prototype = -1;
  Affine table_to_image;  ///< the pose of the pool's closest match (table px -> working px)
  std::vector<int> places;  ///< the places that voted for it (indices into the places voting)
  float distance = 0.f;   ///< the closest match's descriptor distance
};

/// The similarity table -> image that match `c` implies for rays read at `place`:
/// the match's table point onto the place, its heading bin onto the place's
/// heading, its scale (ProposalCandidate::log_scale).
Affine matchPose(const ProposalCandidate& c, const RayPlace& place);

/// The votes of `places`, `per_place` matches each (the index's nearest),
/// pooled: two votes agree when they are of the same prototype and put its
/// centre within a tenth of its image size (at least 4 px), its turn within
/// 15 degrees and its scale within 15%; a pool counts each place once. Most
/// votes first, then the closest match. Places whose rays do not all meet an
/// edge do not vote.
std::vector<PoseVote> poolPoseVotes(const ProposalIndex& index, const PrototypeMemory& memory,
                                    const RadialScanner& scanner, const std::vector<RayPlace>& places,
                                    int per_place);
}  // namespace amcr
