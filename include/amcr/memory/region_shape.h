// Cuts a shape out of a region of a camera image, for teaching a prototype at
// runtime (the node's ~teach service): edges inside the region only, closed
// into outlines, and the largest closed outline filled as the silhouette.
//
// The method: the region (a polygon, clipped to the image) is a mask eroded by
// kRegionInset px, so the region's own border never counts as an edge. In it,
// Canny finds the edges of the image smoothed by params.blur_sigma, with the
// thresholds of params.edge_threshold (a grey-level step over 2 px, as the
// radial scans use it: high = the step, low = half of it). A morphological
// closing of kClosingSize px bridges small gaps; the outer contours of the
// closed edge map (cv::findContours, RETR_EXTERNAL) are the candidates. The
// shape is the largest of them that does not touch the inset region's border
// and whose interior (the filled contour less the closed edges) covers at
// least kMinRegionShare of the region and kMinShapeArea px; its filled
// contour is the silhouette. A stroke (an open line) has no interior and is
// never a shape. When no outline stays clear of the border, a line may cross
// the shape (a cable, a table edge): then the pixels free of edges that
// connect to the border are taken as outside, the rest is opened by
// kLineCutSize px to cut off the line's stubs, and the largest part that
// touches the border no more than a stub or two would (grown back within the
// opening's reach) is the shape. Canny's edges are 1 px wide on the outline, so the filled
// contour needs no erosion: it holds the outline's edge pixels, on average
// half a px outside the true outline (the area 1-4 % above the truth on the
// drawn shapes of test/test_region_shape.cpp).
//
// A shape with edges of its own inside its outline (a part's print, a
// marker's cells: at least kMinInnerEdgePixels Canny pixels kInnerEdgeInset
// px or more inside it) is also cut as a grey template: the image's grey
// levels over the same box, the silhouette as its alpha channel, so that the
// prototype taught from it keeps its inner edges (edge_model.h).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"

namespace amcr
{
/// Px the region's mask is eroded by before edges are looked for: its own
/// border never counts as an edge.
constexpr int kRegionInset = 3;
/// Side of the closing's structuring element (an ellipse), px: gaps in an
/// outline up to about this wide are bridged.
constexpr int kClosingSize = 5;
/// Side of the opening (an ellipse) that cuts a line crossing the shape off
/// it, px: a line whose closed edges are narrower is cut, as are the two
/// edges of a wider one (its inside connects to the border).
constexpr int kLineCutSize = 9;
/// Least share of the region's area the shape's interior covers.
constexpr double kMinRegionShare = 0.02;
/// Least area of the shape's interior, px.
constexpr double kMinShapeArea = 64.0;
/// Margin of empty pixels around the shape in the cut silhouette, px.
constexpr int kSilhouetteMargin = 8;
/// Px inside the outline from which an edge is the shape's own, not its outline's.
constexpr int kInnerEdgeInset = 3;
/// Least Canny pixels inside the outline that make the cut a grey template.
constexpr int kMinInnerEdgePixels = 24;

/// The 4 corners of the rectangle at (x, y) (its top left corner) of
/// `width` x `height`, input px: a region for cutShape().
std::vector<cv::Point2f> rectangleRegion(double x, double y, double width, double height);

/// What cutShape() found.
struct CutShape
{
  /// CV_8UC1, 255 inside the shape on 0, cropped to the shape's bounding box
  /// plus kSilhouetteMargin px; empty on failure.
  cv::Mat silhouette;
  /// Where the silhouette lies in the input image, px (may reach past the
  /// image's border by the margin).
  cv::Rect bounds;
  /// When the shape has inner edges: the image's grey levels over `bounds`
  /// (its border repeated past the image's) with the silhouette as alpha,
  /// CV_8UC4 (BGRA); else empty.
  cv::Mat grey_template;
  /// Empty on success; otherwise a sentence saying why no shape was cut.
  std::string why;

  bool ok() const { return why.empty(); }
  /// What a prototype is taught from: the grey template when there is one, else the silhouette.
  const cv::Mat& prototypeImage() const { return grey_template.empty() ? silhouette : grey_template; }
};

/// Cuts the shape enclosed by edges inside `region` (a polygon of at least 3
/// points, input px, pixel-centre convention) of `image` (CV_8UC1 or
/// CV_8UC3, BGR). Uses params.edge_threshold and params.blur_sigma. Never
/// throws for a bad region or image: the answer's `why` says what is wrong
/// (an empty region, one outside the image, an empty or unsupported image, no
/// edges in the region, no closed outline in it).
CutShape cutShape(const cv::Mat& image, const std::vector<cv::Point2f>& region, const EdgeParams& params);
}  // namespace amcr
