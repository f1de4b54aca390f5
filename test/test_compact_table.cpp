// Compact tables (table_stride): one scan per block of the prototype's pixels, and how far their
// lookups stay from the exact table's.
#include <cmath>
#include <cstddef>
#include <iostream>

#include <gtest/gtest.h>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/ray_directions.h"
#include "cached_prototype.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;
using amcr_test::cachedPrototype;

// Compact tables, so that a memory of a thousand prototypes and more fits:
// a table at stride s holds one scan per s x s
// block, at the block's centre, so its size is the nodes times the bins and
// every pixel of a block reads the same scan.
TEST(CompactTable, StrideDividesTheNodesAndPixelsOfABlockShareOneScan)
{
  const amcr::Params defaults;
  const amcr::Prototype& full = cachedPrototype(ShapeId::kStar);
  for (int stride : {2, 4})
  {
    const amcr::Prototype compact("star", amcr_test::drawPrototype(ShapeId::kStar), defaults.prototype_size,
                                  defaults.edge_threshold, 1.0, stride);
    ASSERT_EQ(compact.width(), full.width());
    ASSERT_EQ(compact.tableStride(), stride);
    const std::size_t cols = (compact.width() + stride - 1) / stride, rows = (compact.height() + stride - 1) / stride;
    EXPECT_EQ(compact.tableBytes(), cols * rows * amcr::kDirectionBins) << "stride " << stride;
    for (int y = 0; y < compact.height(); ++y)
      for (int x = 0; x < compact.width(); ++x)
        ASSERT_EQ(compact.rawDistances(x, y), compact.rawDistances(x - x % stride, y - y % stride))
            << "stride " << stride << " at " << x << ", " << y;
  }
}

// The error a compact table's lookups make against the exact table, over
// every interior pixel (where M-particles are seeded) and every direction
// of the five drawn shapes at the default size (2.0 M lookups). Stated bound
// (docs/configuration.md, "Compact tables"; measured 68.5%, 91.4%, 1.50 px, 0.20%), at
// stride 2: 65% of the lookups within 0.5 px and 88% within 1 px of the
// exact distance, a mean error below 1.8 px, and "edge" against "no edge"
// disagreeing in under 0.5%. At stride 4 (measured 71.4%, 91.0%, 2.84 px,
// 0.60%): the same shares within 1.5 and 3 px, a mean below 3.3 px, under
// 1% disagreeing. The ray's origin moves by up to (s - 1) / sqrt(2) px
// (0.71 px at stride 2); where the ray meets the outline at a glancing
// angle that moves the hit far along it, so the tail is long: the bound is
// on the shares and the mean, not on the largest error.
TEST(CompactTable, LookupsStayWithinTheStatedBoundOfTheExactTable)
{
  const amcr::Params defaults;
  struct Bound
  {
    int stride;
    double near_px, far_px;      // error bounds
    double near_share, far_share;  // shares of lookups within them
    double mean_px, disagree_share;
  };
  for (const Bound& b : {Bound{2, 0.5, 1.0, 0.65, 0.88, 1.8, 0.005}, Bound{4, 1.5, 3.0, 0.65, 0.88, 3.3, 0.01}})
  {
    double sum = 0;
    long both = 0, near = 0, far = 0, disagree = 0, total = 0;
    for (ShapeId shape : amcr_test::allShapes())
    {
      const amcr::Prototype& full = cachedPrototype(shape);
      const amcr::Prototype compact(amcr_test::shapeName(shape), amcr_test::drawPrototype(shape),
                                    defaults.prototype_size, defaults.edge_threshold, 1.0, b.stride);
      for (const cv::Point& at : full.interior())
          for (int bin = 0; bin < amcr::kDirectionBins; ++bin)
          {
            const float exact = full.distance(at.x, at.y, bin), looked_up = compact.distance(at.x, at.y, bin);
            ++total;
            if ((exact < 0) != (looked_up < 0))
            {
              ++disagree;
              continue;
            }
            if (exact < 0)
              continue;
            const double e = std::abs(exact - looked_up);
            ++both;
            sum += e;
            near += e <= b.near_px;
            far += e <= b.far_px;
          }
    }
    const double near_share = static_cast<double>(near) / both, far_share = static_cast<double>(far) / both;
    const double mean = sum / both, disagree_share = static_cast<double>(disagree) / total;
    std::cout << "[ compact  ] stride " << b.stride << ": " << 100 * near_share << "% within " << b.near_px << " px, "
              << 100 * far_share << "% within " << b.far_px << " px, mean " << mean << " px, edge/no edge "
              << 100 * disagree_share << "% of " << total << " lookups\n";
    EXPECT_GE(near_share, b.near_share) << "stride " << b.stride;
    EXPECT_GE(far_share, b.far_share) << "stride " << b.stride;
    EXPECT_LT(mean, b.mean_px) << "stride " << b.stride;
    EXPECT_LT(disagree_share, b.disagree_share) << "stride " << b.stride;
  }
}
}  // namespace
