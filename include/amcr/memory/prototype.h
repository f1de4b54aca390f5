// One prototype of the memory: a silhouette normalised to a fixed size, its
// outline, and the radial-scan lookup table of paper 4.4, so that M-particles
// never touch prototype pixels.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/memory/outline_point.h"
#include "amcr/memory/radial_table.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
class RadialScanner;

/// Where the original image lies in a prototype's table image.
struct TablePlacement
{
  cv::Size original_size;          ///< px
  cv::Matx23d original_to_table;   ///< OpenCV pixel-centre convention
  cv::Matx23d table_to_original;
};

/// How a prototype's image was read (edge_model.h).
enum class PrototypeKind
{
  kSilhouette,  ///< two grey levels: the shape's outline (and its holes') is the model
  kTemplate,    ///< any grey image: all its edges, inner ones included, are the model
};

class Prototype
{
public:
  /// Distance stored for "no edge on this ray".
  static constexpr std::uint8_t kNoEdge = RadialTable::kNoEdge;
  /// The largest table stride (Prototype()).
  static constexpr int kMaxTableStride = 4;
  /// Table distances are stored in units of this many px (0.5 px).
  static constexpr float kDistanceUnit = RadialTable::kDistanceUnit;

  /// Margin around the normalised shape in the table, px, for a shape whose
  /// longer side is `size` px: rays starting just outside the shape see it.
  static int tableMargin(int size) { return size / 8 > 8 ? size / 8 : 8; }

  /// Builds the prototype from a silhouette image of either polarity (the
  /// background is the colour that dominates the image border), or, when
  /// the image is not a silhouette (isSilhouette()) or has an alpha channel
  /// that is not opaque everywhere, from a grey template: its edges are the
  /// model (kind(), edge_model.h), found with the thresholds the camera
  /// image gets (`edge_threshold` where the local edge strength reaches
  /// `edge_full_strength`, edge_thresholds.h), and the alpha channel, when
  /// there is one, is where the object lies; with `keep_polarity` its edges
  /// count only with the template's polarity (polarity()). `size` is
  /// the longer side of the shape in the table, px. The table holds what a
  /// RadialScanner with `edge_threshold` finds in the mask smoothed by
  /// `blur_sigma` (scanImage()). Throws MemoryError when the image is empty
  /// or holds no shape (no edges). `table_stride` (1-4) is the spacing of
  /// the table's nodes, table px: 1 holds every pixel's scan (exact
  /// lookups); s holds one scan per s x s block of pixels, taken at the
  /// block's centre, which every pixel of the block reads (s^2 times less
  /// memory and build time, the ray's origin off by up to (s - 1) / sqrt(2)
  /// px: the tables of a large memory fit in RAM). `instance` names this
  /// image among the label's instances (the file it came from); "" = the
  /// label.
  Prototype(const std::string& label, const cv::Mat& image, int size, double edge_threshold, double blur_sigma = 1.0,
            int table_stride = 1, const std::string& instance = std::string(), double edge_full_strength = 0.0,
            bool keep_polarity = false);

  /// The image the table was scanned in: the smoothed mask of a silhouette,
  /// the smoothed grey of a template (its border replicated into the margin).
  cv::Mat scanImage() const;

  /// Whether the model is a silhouette's outline or a grey template's edges.
  PrototypeKind kind() const { return kind_; }
  bool isTemplate() const { return kind_ == PrototypeKind::kTemplate; }
  /// The polarity an image edge must have to count for the score: +1 for a
  /// template read with keep_polarity (the grey rising along its points'
  /// normals, as in the template); 0 = either, the one most points show.
  int polarity() const { return isTemplate() && keep_polarity_ ? 1 : 0; }

  /// The label recognitions carry: what the shape is ("bird").
  const std::string& label() const { return label_; }
  /// Which of the label's instances this is: the image file, relative to
  /// the prototype directory ("bird/bird-3.png", or "star.png" for a loose
  /// file), or the label for a prototype made from an image in memory.
  const std::string& instance() const { return instance_; }

  /// Table size (the normalised image with its margin).
  int width() const { return mask_.cols; }
  int height() const { return mask_.rows; }

  /// The normalised silhouette, CV_8UC1, 255 inside the shape; for a
  /// template, the object's region: its alpha channel, else the convex hull
  /// of its edge points.
  const cv::Mat& mask() const { return mask_; }

  /// Distance, table px, from pixel (x, y) to the first edge in direction bin
  /// `bin` (from the centre of its node when tableStride() > 1); negative
  /// when no edge. (x, y) must lie inside the table.
  float distance(int x, int y, int bin) const
  {
    const std::uint8_t d = rawDistances(x, y)[bin];
    return d == kNoEdge ? -1.f : d * kDistanceUnit;
  }

  /// The kDirectionBins distances at pixel (x, y), raw (kNoEdge or units of
  /// kDistanceUnit): those of the node whose block holds the pixel.
  const std::uint8_t* rawDistances(int x, int y) const { return table_.rawDistances(x, y); }

  /// Spacing of the table's nodes, table px (1 = every pixel).
  int tableStride() const { return table_.stride(); }

  /// Pixels inside the shape (table coordinates), where M-particles are seeded.
  const std::vector<cv::Point>& interior() const { return interior_; }

  /// The outline, evenly resampled, table coordinates, normals outwards; for
  /// a template, its edge points, normals towards rising grey.
  const std::vector<OutlinePoint>& outline() const { return outline_; }

  /// Maps the original image's pixel coordinates to table coordinates
  /// (OpenCV pixel-centre convention), and back.
  const cv::Matx23d& originalToTable() const { return placement_.original_to_table; }
  const cv::Matx23d& tableToOriginal() const { return placement_.table_to_original; }

  /// Centre of the shape's bounding box, table px.
  cv::Point2d centre() const { return {0.5 * (mask_.cols - 1), 0.5 * (mask_.rows - 1)}; }

  /// Size of the original image, px.
  cv::Size originalSize() const { return placement_.original_size; }

  /// Memory held by the lookup table, bytes.
  std::size_t tableBytes() const { return table_.bytes(); }

  /// Everything but the label as bytes (prototype_bytes.cpp), for the table
  /// cache; fromBytes() gives the same prototype back under `label` and
  /// `instance` ("" = the label). Both in
  /// the machine's byte order. fromBytes() throws MemoryError naming what
  /// does not fit (a size, a point outside the table, bytes missing or left).
  std::vector<std::uint8_t> toBytes() const;
  static std::shared_ptr<const Prototype> fromBytes(const std::string& label, const std::uint8_t* data,
                                                    std::size_t size, const std::string& instance = std::string());

private:
  Prototype() = default;  // for fromBytes()
  /// The silhouette's mask, normalised into the table; returns its box in the image.
  cv::Rect readSilhouette(const cv::Mat& grey, int size);
  /// The template's scan image, region and edge points; returns its box in the image.
  cv::Rect readTemplate(const cv::Mat& grey, const cv::Mat& alpha, int size, double edge_threshold,
                        double edge_full_strength);
  void buildTable(int stride, double edge_threshold, double edge_full_strength);

  void buildOutline();

  PrototypeKind kind_ = PrototypeKind::kSilhouette;
  bool keep_polarity_ = false;
  double blur_sigma_ = 1.0;

  std::string label_;
  std::string instance_;
  cv::Mat mask_;
  cv::Mat template_scan_;  // a template's scan image (empty for a silhouette: made from mask_)
  RadialTable table_;
  std::vector<cv::Point> interior_;
  std::vector<OutlinePoint> outline_;
  TablePlacement placement_;
};
}  // namespace amcr
