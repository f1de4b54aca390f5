// The alignment of one prototype onto a look-alike (discriminative_places.h):
// two prototypes of alike shapes (a bird with and without a crest) are
// normalised each to its own bounding box, so the same part lies at
// different table px in the two, and MPEG-7's instances of a class are drawn
// in any orientation. Places where the index finds the two alike give
// corresponding points; a similarity fitted to them robustly, then refined
// on the two outlines, maps one table onto the other.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"

namespace amcr
{
class Prototype;

/// The result of alignPrototypes().
struct PrototypeAlignment
{
  Affine a_to_b = identityAffine();  ///< table px of a -> table px of b (a similarity)
  int inliers = 0;                   ///< corresponding places the similarity keeps
  double outline_distance = 0.0;     ///< table px of b: the larger median distance, a's mapped outline to b's or back
};

/// Aligns prototype `a` onto `b` from corresponding places (`in_a[i]` of a
/// looks like `in_b[i]` of b, table px): the similarity (rotation, scale,
/// shift, no mirror) that most of them agree with (RANSAC, `tolerance` table
/// px of b), refined by fitting each outline's points to the other's
/// nearest (iterated, the farthest third of each dropped). False when fewer
/// than `min_inliers` places agree, or the outlines stay more than
/// `max_outline_distance` px apart (the median, either way): the shapes are
/// not alike.
bool alignPrototypes(const Prototype& a, const Prototype& b, const std::vector<cv::Point2d>& in_a,
                     const std::vector<cv::Point2d>& in_b, double tolerance, int min_inliers,
                     double max_outline_distance, PrototypeAlignment& out);
}  // namespace amcr
