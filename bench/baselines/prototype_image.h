// A prototype file as the baselines take it: a silhouette, or a grey template when amcr reads the
// file as one (amcr::Prototype: an alpha channel short of opaque, or an image that is not two grey
// levels, amcr::isSilhouette), so that AMCR and the baselines are given the same kind of prototype.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "baseline.h"

namespace amcr_bench
{
/// The prototype `label` from `image`, the file decoded unchanged (cv::IMREAD_UNCHANGED: 1, 3 or 4
/// channels of a depth amcr::toGray8 takes). A grey template gets amcr's grey (amcr::toGray8) and as
/// its mask its region: where its alpha channel is at least 128, else the whole image. A silhouette's
/// mask is its grey; a flat image stays a (blank) silhouette, which every baseline refuses by name.
/// Throws std::invalid_argument naming the label for an image amcr::toGray8 refuses.
PrototypeImage prototypeImage(const std::string& label, const cv::Mat& image);

/// prototypeImage() of the file at `path`, a silhouette's mask read as grey by the decoder
/// (cv::IMREAD_GRAYSCALE), as the benchmark has always read it. Throws std::invalid_argument naming
/// the file when it cannot be read or holds an image of a kind the baselines cannot take.
PrototypeImage readPrototypeImage(const std::string& label, const std::string& path);
}  // namespace amcr_bench
