#include "amcr/memory/radial_table.h"

#include <algorithm>
#include <cmath>

#include "amcr/base/parallel_for.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
RadialTable::RadialTable(const cv::Size& size, int stride)
  : stride_(stride)
  , node_cols_((size.width + stride - 1) / stride)
  , node_rows_((size.height + stride - 1) / stride)
  , cells_(static_cast<std::size_t>(node_cols_) * node_rows_ * kDirectionBins, kNoEdge)
{
}

void RadialTable::fill(const RadialScanner& scanner, const cv::Size& size)
{
  const int cols = size.width, rows = size.height;
  // A node sits at the centre of its stride x stride block of pixels.
  const float node_offset = 0.5f * static_cast<float>(stride_ - 1);
  float dir_x[kDirectionBins], dir_y[kDirectionBins];
  for (int b = 0; b < kDirectionBins; ++b)
  {
    dir_x[b] = static_cast<float>(std::cos(binToAngle(b)));
    dir_y[b] = static_cast<float>(std::sin(binToAngle(b)));
  }
  // A row of nodes per piece of work, on OpenCV's threads (parallel_for.h).
  parallelFor(node_rows_, resolveThreads(0), [&](int j) {
    for (int i = 0; i < node_cols_; ++i)
    {
      std::uint8_t* cell = &cells_[(static_cast<std::size_t>(j) * node_cols_ + i) * kDirectionBins];
      const float x = std::min(static_cast<float>(cols - 1), static_cast<float>(i * stride_) + node_offset);
      const float y = std::min(static_cast<float>(rows - 1), static_cast<float>(j * stride_) + node_offset);
      for (int b = 0; b < kDirectionBins; ++b)
      {
        const RayHit hit = scanner.scan(x, y, dir_x[b], dir_y[b]);
        if (hit.valid && hit.distance <= kMaxDistance)
          cell[b] = static_cast<std::uint8_t>(std::lround(hit.distance / kDistanceUnit));
      }
    }
  });
}
}  // namespace amcr
