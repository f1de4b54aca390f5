// The truth of a benchmark sequence (bench/make_sequences writes <sequence>/truth.json): what is
// in view in each frame and where, as prototype -> image maps.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace amcr_bench
{
/// One object in view.
struct TruthObject
{
  std::string label;
  /// The image file the shown shape was drawn from ("dog-10.png"; the truth's targets), "" when
  /// the truth does not say.
  std::string source;
  /// The size of the prototype image the truth maps from (px): the shown shape's own image, which
  /// the memory holds only when it holds a prototype of this label and size.
  cv::Size prototype_size;
  /// Original prototype px -> image px (pixel centres), a homography (an affine has 0 0 1 as its
  /// last row). Several when the shape looks the same under a symmetry the truth names (a
  /// half-turn symmetric part, the real camera's target): each is as right as the others.
  std::vector<cv::Matx33d> prototype_to_image;
};

/// One frame: `known` false when the truth could not be found in it (the real camera's frames
/// where the target's own pattern was not seen); it is then not scored.
struct TruthFrame
{
  bool known = true;
  std::vector<TruthObject> objects;
};

/// Reads a sequence's truth.json: one entry per frame, in frame order. std::runtime_error naming
/// the file and what is wrong when it cannot be read or is not of that form.
std::vector<TruthFrame> readSequenceTruth(const std::string& path);
}  // namespace amcr_bench
