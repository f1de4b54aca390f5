// A grey template with inner structure, as a user cuts one from a photo of a
// part (a dark square body with a light disc and a light bar on it, on a
// board of middle grey), and scenes that show it, its reversed contrast or its
// plain outline over clutter.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "scene_drawing.h"

namespace amcr_test
{
/// Side of the template image, px.
constexpr int kTemplateSide = 160;
/// The part's square body in the template image.
const cv::Rect kTemplateBody(20, 20, 120, 120);

/// The template: board grey 150 around a body of grey 45 holding a disc
/// (grey 215, off-centre towards the top left) and a bar (grey 185, along the
/// bottom), so that no turn of it looks the same. CV_8UC1, kTemplateSide px.
cv::Mat drawGreyTemplate();

/// The body alone as a silhouette (255 on 0): the template's outline without its inner edges.
cv::Mat drawTemplateOutline();

/// What a scene shows under `truth` (template px -> image px).
enum class TemplateView
{
  kPart,      ///< the part's body with its disc and bar
  kReversed,  ///< the same scene with every grey reversed (255 - grey): a negative, a part lit from behind
  kPlain,     ///< a plain dark square of the body's size: the outline, no inner edges
};

/// `frames` frames of the part's body drawn as `view` under `truth` over the
/// background and distractors of `clutter` (kept off its place), each frame
/// with its own noise (seed clutter.seed * 1000 + frame, added after a reversal).
std::vector<cv::Mat> templateOverClutter(TemplateView view, const amcr::Affine& truth, const Clutter& clutter,
                                         int frames);

/// Template px -> image px: the template's centre at `centre`, turned by
/// `turn_deg` degrees, scaled by `scale`.
amcr::Affine templatePlacement(double turn_deg, const cv::Point2d& centre, double scale);

/// One frame of `view` under `truth` over seven random shapes, an ell and a
/// flag (the clutter of the template tests), drawn with `clutter_seed`.
cv::Mat templateFrame(TemplateView view, const amcr::Affine& truth, std::uint64_t clutter_seed);
}  // namespace amcr_test
