// Inputs the speed benchmarks share, drawn in code (test/scene_drawing.h):
// memories of drawn prototypes and 640x480 sequences.
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/memory/prototype_memory.h"

namespace amcr_bench
{
/// A memory of `count` prototypes (at most 127) cycling through the drawn
/// shapes, built once per count.
std::shared_ptr<const amcr::PrototypeMemory> cachedMemory(int count);

/// 16 640x480 frames of the arrow standing over clutter.
const std::vector<cv::Mat>& staticFrames();

/// 200 640x480 frames of the arrow moving over clutter on a Lissajous
/// curve, turning 2.5 degrees a frame.
const std::vector<cv::Mat>& movingFrames();
}  // namespace amcr_bench
