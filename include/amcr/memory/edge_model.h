// A grey template read as an edge model: what a prototype is when its image
// is not a silhouette (a part cut from a photo, a marker, a print with inner
// structure). The paper's lookup tables hold, for each prototype pixel and
// direction, the distance to the next edge (paper 4.4); a template's own edges
// give exactly that, inner ones included, and its edge points (with the
// direction of their grey gradient) are what the score checks on the image.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/memory/outline_point.h"

namespace amcr
{
/// Whether `grey` (CV_8UC1) is a silhouette: two grey levels, up to the
/// antialiasing of its outline. The pixels farther than a tenth of the
/// contrast from both levels (Otsu's two class means) are at most
/// kSilhouetteMidShare of the image; a flat image is not one.
bool isSilhouette(const cv::Mat& grey);

/// The share of an image's pixels that may lie off a silhouette's two grey levels.
constexpr double kSilhouetteMidShare = 0.05;

/// An image as a prototype reads it: its grey (toGray8) and, for an image
/// with four channels, its alpha channel as 8-bit grey, left empty when it
/// is opaque everywhere (it says nothing then). Throws InputError for an
/// image toGray8 refuses.
void prototypeGreyAndAlpha(const cv::Mat& image, cv::Mat& grey, cv::Mat& alpha);

/// Whether the image of `grey` and `alpha` (prototypeGreyAndAlpha) is read
/// as a grey template: it has an alpha channel, or it is no silhouette.
bool readAsTemplate(const cv::Mat& grey, const cv::Mat& alpha);

/// Px: a template's chains of edge pixels shorter than this are texture, not
/// its shape (templateEdgePoints' `min_length` as a prototype reads it).
constexpr int kMinTemplateChain = 8;

/// The edge points of a template's scan image (`scan_image`, CV_8UC1, the
/// table's size): the pixels whose 2 px grey step along the gradient reaches
/// `thresholds` there and is a maximum along it (non-maximum suppression, as
/// in Canny), placed to a fraction of a pixel by a parabola across the edge,
/// one per 2 x 2 pixels, in chains of at least `min_length` pixels, inside
/// `region` (CV_8UC1, non-zero where points may lie; empty = everywhere).
/// The normal points towards rising grey, so a template's inner edges keep
/// their polarity relative to each other.
std::vector<OutlinePoint> templateEdgePoints(const cv::Mat& scan_image, double edge_threshold, double full_strength,
                                             int min_length, const cv::Mat& region);

}  // namespace amcr
