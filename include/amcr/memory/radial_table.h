// The radial-scan lookup table of one prototype (paper 4.4): for every node
// of the table image, the distance to the first edge in each of the
// kDirectionBins directions, so that M-particles never touch prototype
// pixels. Nodes sit one per stride x stride block of pixels, at the block's
// centre; every pixel of the block reads its node.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/scan/ray_directions.h"

namespace amcr
{
class RadialScanner;

class RadialTable
{
public:
  /// Distance stored for "no edge on this ray".
  static constexpr std::uint8_t kNoEdge = 255;
  /// Distances are stored in units of this many px (0.5 px).
  static constexpr float kDistanceUnit = 0.5f;
  /// The largest distance stored, px: the largest a uint8 in kDistanceUnit holds.
  static constexpr float kMaxDistance = 127.f;

  RadialTable() = default;
  /// A table of an image of `size` px with nodes every `stride` px, every
  /// ray kNoEdge until fill().
  RadialTable(const cv::Size& size, int stride);

  /// Every node's radial scans by `scanner` over an image of the table's
  /// size (paper 4.4): a ray that meets no edge within kMaxDistance
  /// stays kNoEdge.
  void fill(const RadialScanner& scanner, const cv::Size& size);

  /// The kDirectionBins distances at pixel (x, y), raw (kNoEdge or units of
  /// kDistanceUnit): those of the node whose block holds the pixel.
  const std::uint8_t* rawDistances(int x, int y) const
  {
    return &cells_[(static_cast<std::size_t>(y / stride_) * node_cols_ + x / stride_) * kDirectionBins];
  }

  /// Spacing of the nodes, px (1 = every pixel).
  int stride() const { return stride_; }
  /// The raw distances, node by node, row by row: what the table cache stores.
  std::size_t bytes() const { return cells_.size(); }
  const std::uint8_t* data() const { return cells_.data(); }
  std::uint8_t* data() { return cells_.data(); }

private:
  int stride_ = 1;
  int node_cols_ = 0;  // ceil(width / stride_)
  int node_rows_ = 0;
  std::vector<std::uint8_t> cells_;  // [node y][node x][bin], the bins of a node side by side
};
}  // namespace amcr
