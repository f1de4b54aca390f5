// Baseline: shape contexts (Belongie, Malik, Puzicha), the paper's comparison, run with
// OpenCV's cv::ShapeContextDistanceExtractor. The candidates are the closed contours of
// the binarised frame (as for the Hu-moment baseline, plus a morphological clean-up that
// cuts crossing lines off, an edge test and one contour per outline); each is resampled
// and compared by computeDistance with every prototype's outline, from several starting
// orientations (an affine transformer aligns them); a candidate goes to its nearest
// prototype, and the affine is fitted to the point matches of the extractor's last
// iteration, which are the detection's correspondences.
// A grey template (prototype_image.h) has no outline to compare: as in Belongie et al., whose
// points are sampled from a shape's inner and outer edges, its points are its edge model as amcr
// reads it (amcr::Prototype), spread over it, and they are compared with the frame's edge points
// found the same way (amcr::templateEdgePoints) within a candidate's contour, spread the same way.
// (With Canny's pixels on the frame instead, the drawn part of the tests matched at costs of
// 0.09-0.12, no better than clutter.) The candidates are still closed contours of the binarised
// frame: a template is found only where an outline of it (a tag's black square, a box's sides)
// stands out as one, and its pose comes from the points' matches alone.
#pragma once

#include <vector>

#include <opencv2/shape.hpp>

#include "baseline.h"

namespace amcr_bench
{
struct ShapeContextConfig
{
  int points = 50;     ///< points per outline, evenly spaced in arc length
  int template_points = 100;  ///< per grey template, and per candidate compared with one: spread over its edges
  int turns = 8;       ///< starting orientations of the prototype, evenly spread over the full turn
  int iterations = 3;  ///< the extractor's match-and-align rounds (OpenCV's default)
  // Extractor distance (shape-context cost, 0-1, for 50 points) accepted as a match. Set on drawn scenes
  // (3 silhouettes over random shapes, 2 other silhouettes and lines; rotation, aspect and shear drawn as
  // the benchmark draws them): the shown shape at 0.03-0.096, clutter against memories of 3, 17 and 70
  // prototypes at 0.115 and above.
  double max_distance = 0.1;
  /// The same for a grey template (100 edge points). Set on the drawn part over clutter (test/template_drawing.h,
  /// 1.1 x, 3 clutter seeds x 4 turns): the part at 0.026-0.06 in 10 of 12 views (once at 0.10), clutter
  /// and a plain square of the part's outline at 0.098 and above.
  double template_max_distance = 0.08;
  double max_anisotropy = 4.0;   ///< of a plausible pose: largest / smallest singular value of its affine
  double max_area_change = 1.5;  ///< factor by which the pose may scale the prototype's area off the candidate's
  double ransac_px = 3.0;        ///< inlier distance of the affine fit to the matches, image px (OpenCV's default)
  double min_size = 60.0;        ///< candidate size range: longer side of the contour's bounding box, px
  double max_size = 400.0;
  int max_candidates = 12;   ///< per frame, the largest by area: each costs `turns` matches per prototype
  int adaptive_block = 51;   ///< adaptive-threshold block, px (as the Hu-moment baseline)
  double adaptive_c = 10.0;  ///< adaptive-threshold offset, grey levels
  int clean_px = 7;          ///< binary opening and closing disc, px: thinner lines are cut off the shapes
  double canny_low = 40.0;   ///< Canny thresholds of the edges a candidate's contour must follow
  double canny_high = 80.0;
  double min_edge_share = 0.6;  ///< of a candidate's contour points on an edge (within 1 px)
  double same_box = 0.9;        ///< bounding-box overlap (intersection / union) of two finds of one outline
};

class ShapeContext : public Method
{
public:
  /// Throws std::invalid_argument naming the label when a prototype's mask holds no shape, or a grey
  /// template has too few edges for amcr to read it.
  ShapeContext(const std::vector<PrototypeImage>& prototypes, const ShapeContextConfig& config = ShapeContextConfig());
  std::string name() const override { return "sc"; }
  std::vector<Detection> detect(const cv::Mat& grey) override;

private:
  class MatchRecorder;
  struct Model
  {
    std::string label;
    std::vector<cv::Point2f> points;  ///< the outline resampled (a template's edges spread), original prototype px
    double area = 0.0;                ///< enclosed by the outline (a template's edges' convex hull), px^2
    bool inner_edges = false;         ///< a grey template: compared with the edges within a candidate
  };
  ShapeContextConfig config_;
  std::vector<Model> models_;
  cv::Ptr<MatchRecorder> recorder_;  ///< the extractor's transform algorithm
  cv::Ptr<cv::ShapeContextDistanceExtractor> extractor_;
};
}  // namespace amcr_bench
