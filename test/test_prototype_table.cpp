// The prototype's radial-scan lookup table (paper 4.4) against the naive
// reference (style point 7): a direct scan of the prototype's own
// normalised image with the same scanner. Plus the prototype's mask,
// interior, outline and coordinate maps.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"
#include "amcr/scan/ray_directions.h"
#include "cached_prototype.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;
using amcr_test::cachedPrototype;

// The longest distance the table holds: 254 units of 0.5 px (255 = no edge).
constexpr float kTableLimit = 127.f;

struct SweepStats
{
  long rays = 0;               // rays compared (those not at the table limit)
  long validity_mismatch = 0;  // the table and the direct scan disagree on "edge / no edge"
  long distance_mismatch = 0;  // both found an edge, more than 1 px apart
  long both_valid = 0;
  double worst_distance = 0.0;
  double sum_abs_distance = 0.0;
};

// Sweeps a grid of pixels (every `step` px, inside and outside the shape,
// the margin included) and all 72 direction bins, against a direct scan of
// the prototype's own mask smoothed with `blur_sigma`.
SweepStats sweep(const amcr::Prototype& proto, double edge_threshold, double blur_sigma, int step)
{
  const cv::Mat scan_image = amcr::prepareScanImage(proto.mask(), blur_sigma);
  // Longer than the table can hold (and than any table), so the reference
  // sees every edge.
  const amcr::RadialScanner reference(scan_image, edge_threshold, 4.0 * (proto.width() + proto.height()));
  SweepStats s;
  for (int y = 0; y < proto.height(); y += step)
    for (int x = 0; x < proto.width(); x += step)
      for (int bin = 0; bin < amcr::kDirectionBins; ++bin)
      {
        const amcr::RayHit ref = reference.scanAngle(static_cast<float>(x), static_cast<float>(y), amcr::binToAngle(bin));
        // An edge between 126 and 128 px may fall on either side of the
        // table's limit: not compared.
        if (ref.valid && std::abs(ref.distance - kTableLimit) < 1.f)
          continue;
        const bool ref_valid = ref.valid && ref.distance <= kTableLimit;
        const float d = proto.distance(x, y, bin);
        const bool table_valid = d >= 0.f;
        ++s.rays;
        if (ref_valid != table_valid)
        {
          ++s.validity_mismatch;
          continue;
        }
        if (!ref_valid)
          continue;
        ++s.both_valid;
        const double diff = std::abs(d - ref.distance);
        s.sum_abs_distance += diff;
        s.worst_distance = std::max(s.worst_distance, diff);
        if (diff > 1.0)
          ++s.distance_mismatch;
      }
  return s;
}

struct TableCase
{
  ShapeId shape;
  int size;               // prototype_size, px
  double edge_threshold;  // grey levels
  double blur_sigma;      // px
};

void PrintTo(const TableCase& c, std::ostream* os)
{
  *os << amcr_test::shapeName(c.shape) << " size " << c.size << " threshold " << c.edge_threshold << " blur "
      << c.blur_sigma;
}

class PrototypeTable : public ::testing::TestWithParam<TableCase>
{
};

// Tolerances: a table entry is the direct scan rounded to 0.5 px units, so
// both-valid distances must agree within 1 px. A ray that grazes the shape
// (near-tangent) can flip between "edge" and "no edge", or jump to a farther
// edge, with a sub-pixel change of the scan: at most 1% of the rays may
// disagree in validity, and at most 1% of the both-valid rays in distance.
TEST_P(PrototypeTable, LookupEqualsDirectScan)
{
  const TableCase c = GetParam();
  const amcr::Params defaults;
  std::unique_ptr<amcr::Prototype> own;
  if (c.size != defaults.prototype_size || c.edge_threshold != defaults.edge_threshold ||
      c.blur_sigma != defaults.blur_sigma)
    own = std::make_unique<amcr::Prototype>(amcr_test::shapeName(c.shape), amcr_test::drawPrototype(c.shape), c.size,
                                            c.edge_threshold, c.blur_sigma);
  const amcr::Prototype& proto = own ? *own : cachedPrototype(c.shape);
  const SweepStats s = sweep(proto, c.edge_threshold, c.blur_sigma, 2);
  ASSERT_GT(s.rays, 10000);
  ASSERT_GT(s.both_valid, s.rays / 4) << "too few edges found: the sweep tests nothing";
  const double validity_rate = static_cast<double>(s.validity_mismatch) / s.rays;
  const double distance_rate = static_cast<double>(s.distance_mismatch) / s.both_valid;
  EXPECT_LE(validity_rate, 0.01) << s.validity_mismatch << " of " << s.rays << " rays";
  EXPECT_LE(distance_rate, 0.01) << s.distance_mismatch << " of " << s.both_valid << " rays, worst "
                                 << s.worst_distance << " px";
  // Rounding to 0.5 px units: the mean error of a table lookup is <= 0.125 px
  // for uniformly spread distances; 0.2 px leaves room for the rare flips.
  EXPECT_LT(s.sum_abs_distance / s.both_valid, 0.2);
  RecordProperty("validity_mismatch", std::to_string(s.validity_mismatch) + "/" + std::to_string(s.rays));
  RecordProperty("distance_mismatch", std::to_string(s.distance_mismatch) + "/" + std::to_string(s.both_valid));
}

std::string caseName(const ::testing::TestParamInfo<TableCase>& info)
{
  std::string name = amcr_test::shapeName(info.param.shape) + "_size" + std::to_string(info.param.size) + "_threshold" +
                     std::to_string(static_cast<int>(info.param.edge_threshold)) + "_blur" +
                     std::to_string(static_cast<int>(10 * info.param.blur_sigma));
  return name;
}

// Every shape at the defaults (size 128, threshold 40, blur 1 px).
INSTANTIATE_TEST_SUITE_P(Shapes, PrototypeTable,
                         ::testing::Values(TableCase{ShapeId::kArrow, 128, 40, 1.0},
                                           TableCase{ShapeId::kCrescent, 128, 40, 1.0},
                                           TableCase{ShapeId::kStar, 128, 40, 1.0},
                                           TableCase{ShapeId::kEll, 128, 40, 1.0},
                                           TableCase{ShapeId::kFlag, 128, 40, 1.0}),
                         caseName);
// A parameter sweep: other sizes, thresholds and blurs.
INSTANTIATE_TEST_SUITE_P(Parameters, PrototypeTable,
                         ::testing::Values(TableCase{ShapeId::kStar, 48, 40, 1.0},
                                           TableCase{ShapeId::kStar, 200, 40, 1.0},
                                           TableCase{ShapeId::kArrow, 128, 15, 1.0},
                                           TableCase{ShapeId::kArrow, 128, 90, 1.0},
                                           TableCase{ShapeId::kCrescent, 128, 40, 0.0},
                                           TableCase{ShapeId::kFlag, 96, 40, 2.5}),
                         caseName);

// scanImage() is the image the reference scans.
TEST(Prototype, ScanImageIsTheSmoothedMask)
{
  const amcr::Prototype& proto = cachedPrototype(ShapeId::kArrow);
  const cv::Mat expected = amcr::prepareScanImage(proto.mask(), amcr::Params().blur_sigma);
  const cv::Mat got = proto.scanImage();
  ASSERT_EQ(got.size(), expected.size());
  ASSERT_EQ(got.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(got != expected), 0);
}

// The memory builds its prototypes with the given parameters.
TEST(Prototype, MemoryUsesItsParameters)
{
  amcr::Params params;
  params.prototype_size = 96;
  params.edge_threshold = 30.0;
  params.blur_sigma = 2.0;
  amcr::PrototypeMemory memory;
  memory.add("flag", amcr_test::drawPrototype(ShapeId::kFlag), params);
  const amcr::Prototype& proto = memory[0];
  std::vector<cv::Point> on;
  cv::findNonZero(proto.mask(), on);
  const cv::Rect box = cv::boundingRect(on);
  EXPECT_NEAR(std::max(box.width, box.height), 96, 1.0);
  EXPECT_EQ(cv::countNonZero(proto.scanImage() != amcr::prepareScanImage(proto.mask(), 2.0)), 0);
  const SweepStats s = sweep(proto, 30.0, 2.0, 3);
  EXPECT_LE(static_cast<double>(s.validity_mismatch) / s.rays, 0.01);
  EXPECT_LE(static_cast<double>(s.distance_mismatch) / s.both_valid, 0.01);
}

// A table far from "no edge everywhere": from a pixel in the middle of the
// shape every ray meets the outline.
TEST(Prototype, RaysFromInsideMeetTheOutline)
{
  const amcr::Prototype& proto = cachedPrototype(ShapeId::kEll);
  // The ell's vertical arm, half way up, in table coordinates.
  const cv::Point2d p = amcr::applyAffine(proto.originalToTable(), cv::Point2d(56, 80));
  ASSERT_GT(proto.mask().at<uchar>(cvRound(p.y), cvRound(p.x)), 0);
  for (int bin = 0; bin < amcr::kDirectionBins; ++bin)
    EXPECT_GE(proto.distance(cvRound(p.x), cvRound(p.y), bin), 0.f) << "bin " << bin;
}

TEST(Prototype, NormalisedToTheRequestedSize)
{
  const amcr::Prototype small("crescent", amcr_test::drawPrototype(ShapeId::kCrescent), 64, 40.0);
  for (const amcr::Prototype* p : {&small, &cachedPrototype(ShapeId::kCrescent)})
  {
    const amcr::Prototype& proto = *p;
    const int size = p == &small ? 64 : 128;
    std::vector<cv::Point> on;
    cv::findNonZero(proto.mask(), on);
    ASSERT_FALSE(on.empty());
    const cv::Rect box = cv::boundingRect(on);
    EXPECT_NEAR(std::max(box.width, box.height), size, 1.0);
    // A margin all round: the shape does not touch the table border.
    EXPECT_GT(box.x, 0);
    EXPECT_GT(box.y, 0);
    EXPECT_LT(box.br().x, proto.width());
    EXPECT_LT(box.br().y, proto.height());
  }
}

// The original image's pixel coordinates map onto the table so that the
// shape lands on the mask: every original pixel at least 3 px from the
// outline is inside the shape exactly when its table pixel is in the mask.
TEST(Prototype, OriginalToTableMapsTheShapeOntoTheMask)
{
  for (ShapeId shape : amcr_test::allShapes())
  {
    const cv::Mat image = amcr_test::drawPrototype(shape);
    const amcr::Prototype& proto = cachedPrototype(shape);
    const cv::Matx23d& to_table = proto.originalToTable();
    const cv::Matx23d& to_original = proto.tableToOriginal();
    EXPECT_EQ(proto.originalSize(), image.size());

    const cv::Mat inside = image > 127;
    cv::Mat dist_in, dist_out;
    cv::distanceTransform(inside, dist_in, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    cv::distanceTransform(~inside, dist_out, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    long compared = 0, wrong = 0;
    for (int y = 0; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x)
      {
        if (dist_in.at<float>(y, x) + dist_out.at<float>(y, x) < 3.f)
          continue;  // within 3 px of the outline
        const cv::Point2d t = amcr::applyAffine(to_table, cv::Point2d(x, y));
        const int tx = cvRound(t.x), ty = cvRound(t.y);
        const bool in_mask =
            tx >= 0 && ty >= 0 && tx < proto.width() && ty < proto.height() && proto.mask().at<uchar>(ty, tx) != 0;
        ++compared;
        wrong += in_mask != (inside.at<uchar>(y, x) != 0);
        // And back.
        const cv::Point2d back = amcr::applyAffine(to_original, t);
        ASSERT_NEAR(back.x, x, 1e-6);
        ASSERT_NEAR(back.y, y, 1e-6);
      }
    EXPECT_GT(compared, 20000);
    EXPECT_EQ(wrong, 0) << amcr_test::shapeName(shape) << ": " << wrong << " of " << compared << " pixels";
  }
}

// White-on-black and black-on-white give the same mask. The silhouettes are
// drawn hard-edged (only 0 and 255), so the two images are exact inverses
// and nothing but the polarity differs.
TEST(Prototype, EitherPolarityGivesTheSameMask)
{
  for (ShapeId shape : amcr_test::allShapes())
  {
    const amcr::Prototype white(amcr_test::shapeName(shape), amcr_test::drawPrototype(shape, true, false), 128, 40.0);
    const amcr::Prototype black(amcr_test::shapeName(shape), amcr_test::drawPrototype(shape, false, false), 128, 40.0);
    ASSERT_EQ(white.mask().size(), black.mask().size()) << amcr_test::shapeName(shape);
    EXPECT_EQ(cv::countNonZero(white.mask() != black.mask()), 0) << amcr_test::shapeName(shape);
    EXPECT_GT(cv::countNonZero(white.mask()), 1000) << "the shape, not the background, is 255";
    EXPECT_EQ(white.mask().at<uchar>(0, 0), 0) << "the background is 0";
  }
  // Antialiased edges (grey levels on the outline): still the same mask
  // (measured: 0 differing pixels for all five shapes).
  for (ShapeId shape : {ShapeId::kCrescent, ShapeId::kStar})
  {
    const amcr::Prototype& white = cachedPrototype(shape);
    const amcr::Prototype black(amcr_test::shapeName(shape), amcr_test::drawPrototype(shape, false, true), 128, 40.0);
    ASSERT_EQ(white.mask().size(), black.mask().size()) << amcr_test::shapeName(shape);
    EXPECT_EQ(cv::countNonZero(white.mask() != black.mask()), 0) << amcr_test::shapeName(shape);
  }
}

TEST(Prototype, NoShapeIsAMemoryError)
{
  EXPECT_THROW(amcr::Prototype("uniform", cv::Mat(200, 200, CV_8UC1, cv::Scalar(90)), 128, 40.0), amcr::MemoryError);
  EXPECT_THROW(amcr::Prototype("black", cv::Mat::zeros(200, 200, CV_8UC1), 128, 40.0), amcr::MemoryError);
  EXPECT_THROW(amcr::Prototype("empty", cv::Mat(), 128, 40.0), amcr::MemoryError);
}

TEST(Prototype, InteriorIsInsideTheMask)
{
  for (ShapeId shape : amcr_test::allShapes())
  {
    const amcr::Prototype& proto = cachedPrototype(shape);
    ASSERT_FALSE(proto.interior().empty()) << amcr_test::shapeName(shape);
    for (const cv::Point& p : proto.interior())
    {
      ASSERT_TRUE(p.x >= 0 && p.y >= 0 && p.x < proto.width() && p.y < proto.height());
      ASSERT_NE(proto.mask().at<uchar>(p), 0) << amcr_test::shapeName(shape) << " (" << p.x << ", " << p.y << ")";
    }
  }
}

// Outline points lie on the mask boundary (within 1 px of the centre of a
// pixel whose 4-neighbourhood holds both shape and background), and their
// normals are unit vectors that point out of the shape.
TEST(Prototype, OutlineLiesOnTheMaskBoundary)
{
  for (ShapeId shape : amcr_test::allShapes())
  {
    SCOPED_TRACE(amcr_test::shapeName(shape));
    const amcr::Prototype& proto = cachedPrototype(shape);
    const cv::Mat& mask = proto.mask();
    const auto in = [&](int x, int y) {
      return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uchar>(y, x) != 0;
    };
    const auto on_boundary = [&](int x, int y) {
      const bool c = in(x, y);
      return in(x + 1, y) != c || in(x - 1, y) != c || in(x, y + 1) != c || in(x, y - 1) != c;
    };
    const auto& outline = proto.outline();
    ASSERT_GE(outline.size(), 50u);
    int outward = 0;
    for (const amcr::OutlinePoint& o : outline)
    {
      double best = 1e9;
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx)
        {
          const int x = cvRound(o.position.x) + dx, y = cvRound(o.position.y) + dy;
          if (on_boundary(x, y))
            best = std::min(best, static_cast<double>(std::hypot(x - o.position.x, y - o.position.y)));
        }
      EXPECT_LE(best, 1.0) << "outline point (" << o.position.x << ", " << o.position.y << ")";
      EXPECT_NEAR(std::hypot(o.normal.x, o.normal.y), 1.0, 1e-3);
      const cv::Point2f out = o.position + 2.f * o.normal, back = o.position - 2.f * o.normal;
      outward += !in(cvRound(out.x), cvRound(out.y)) && in(cvRound(back.x), cvRound(back.y));
    }
    // Corners and the thin parts may fool a 2 px probe; 90% must not.
    EXPECT_GE(outward, 0.9 * outline.size()) << outward << " of " << outline.size() << " normals point outwards";
    // The outline covers the whole boundary: no boundary pixel is farther
    // than 3 px from an outline point.
    int far = 0, boundary = 0;
    for (int y = 0; y < mask.rows; ++y)
      for (int x = 0; x < mask.cols; ++x)
      {
        if (!in(x, y) || !on_boundary(x, y))
          continue;
        ++boundary;
        double best = 1e9;
        for (const amcr::OutlinePoint& o : outline)
          best = std::min(best, static_cast<double>(std::hypot(x - o.position.x, y - o.position.y)));
        far += best > 3.0;
      }
    EXPECT_EQ(far, 0) << far << " of " << boundary << " boundary pixels far from the outline";
  }
}

TEST(Prototype, TableBytesIsPixelsTimesBins)
{
  const amcr::Prototype& proto = cachedPrototype(ShapeId::kStar);
  EXPECT_EQ(proto.tableBytes(),
            static_cast<std::size_t>(proto.width()) * proto.height() * amcr::kDirectionBins);
}
}  // namespace
