// The contours that the contour baselines (Hu moments, shape contexts) compare: a
// prototype's outline, and the candidates of a frame, the closed contours of the frame
// binarised by a global (Otsu) and a local (adaptive mean) threshold, each in both
// polarities, since a print may be dark on light or light on dark and a lighting
// gradient defeats a global threshold alone.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace amcr_bench
{
/// The outer contour of the prototype's shape (the largest external contour of mask > 127,
/// all points); empty when the mask holds no shape.
std::vector<cv::Point> prototypeOutline(const cv::Mat& mask);

/// Every contour (cv::RETR_LIST, all points) of the four binarisations, in the order Otsu,
/// Otsu inverted, adaptive, adaptive inverted; `adaptive_block` (px, odd) and `adaptive_c`
/// (grey levels) are the adaptive threshold's block and offset. With `clean_px` above 1, each
/// binary image is first opened, then closed, with a disc of that diameter: the opening cuts a
/// thinner line that crosses a shape off its contour, the closing fills the gap such a line
/// leaves in the other polarity (which would split the background into line-bounded regions).
std::vector<std::vector<cv::Point>> candidateContours(const cv::Mat& grey, int adaptive_block, double adaptive_c,
                                                      int clean_px = 0);
}  // namespace amcr_bench
