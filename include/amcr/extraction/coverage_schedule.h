// Coverage by construction: where the image's own candidates are read
// (pose_votes.h), so that a visible object is proposed within a known number
// of frames, not when a random V-particle happens onto it. A lattice of
// places spaced a third of the smallest object's side covers the image, and
// frame f reads the share of it whose rank falls in bucket f mod K: every
// place within K frames. The rank is the lattice cell's value in Roberts' R2
// sequence (a low-discrepancy sequence), so each frame's share is spread
// over the whole image, not a band of it. Each round of K frames shifts the
// lattice within a cell and turns the rays by the next R2 values, so the
// rounds read new places and headings. Places inside held objects are
// skipped: they are explained.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/filter/particles.h"

namespace amcr
{
/// The lattice's spacing for objects whose longer side is at least
/// `min_object_size` px: a third of it, at least kMinCoverageSpacing px.
double coverageSpacing(double min_object_size);
constexpr double kMinCoverageSpacing = 6.0;

/// The places of `frame` (counted from 0) on an image of `size`: the lattice
/// cells of spacing `spacing` px whose R2 rank is in bucket frame mod `frames`,
/// outside every polygon of `skip`. Throws ParameterError for a spacing
/// below 1 px or fewer than 1 frame.
std::vector<RayPlace> coveragePlaces(cv::Size size, double spacing, int frames, std::int64_t frame,
                                     const std::vector<std::vector<cv::Point2f>>& skip = {});
}  // namespace amcr
