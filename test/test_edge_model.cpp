// A prototype from a grey template (edge_model.h): which images are read as
// silhouettes and which as templates, the template's edge model against
// Canny's edges, its table against a direct scan of its own grey image, its
// alpha channel as its region, and its bytes for the table cache.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/memory/edge_model.h"
#include "amcr/memory/edge_model_picture.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/edge_thresholds.h"
#include "amcr/scan/radial_scan.h"
#include "amcr/scan/ray_directions.h"
#include "scene_drawing.h"
#include "template_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kSize = 128;
constexpr double kThreshold = 40.0, kFullStrength = 100.0;

amcr::Prototype templatePrototype(const cv::Mat& image)
{
  return amcr::Prototype("part", image, kSize, kThreshold, 1.0, 1, "", kFullStrength);
}

/// Distance, px, from `p` to the nearest non-zero pixel of `edges`, via its distance transform.
double distanceToEdges(const cv::Mat& edge_distance, const cv::Point2f& p)
{
  const int x = std::clamp(cvRound(p.x), 0, edge_distance.cols - 1), y = std::clamp(cvRound(p.y), 0, edge_distance.rows - 1);
  return edge_distance.at<float>(y, x);
}

cv::Mat distanceTo(const cv::Mat& edges)
{
  cv::Mat inverted, distance;
  cv::bitwise_not(edges, inverted);
  cv::distanceTransform(inverted, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}
}  // namespace

TEST(EdgeModel, SilhouettesAreReadAsBeforeTemplatesAsTemplates)
{
  for (ShapeId id : amcr_test::allShapes())
  {
    EXPECT_TRUE(amcr::isSilhouette(amcr_test::drawPrototype(id))) << amcr_test::shapeName(id);
    EXPECT_TRUE(amcr::isSilhouette(amcr_test::drawPrototype(id, false, true))) << amcr_test::shapeName(id);
    EXPECT_FALSE(amcr::Prototype("s", amcr_test::drawPrototype(id), kSize, kThreshold).isTemplate());
  }
  EXPECT_TRUE(amcr::isSilhouette(amcr_test::drawTemplateOutline()));
  EXPECT_FALSE(amcr::isSilhouette(amcr_test::drawGreyTemplate()));
  EXPECT_TRUE(templatePrototype(amcr_test::drawGreyTemplate()).isTemplate());
  // A flat image is neither: no edges.
  EXPECT_FALSE(amcr::isSilhouette(cv::Mat(50, 50, CV_8UC1, cv::Scalar(90))));
}

TEST(EdgeModel, TemplateModelHoldsItsInnerEdgesAndMatchesCanny)
{
  const amcr::Prototype part = templatePrototype(amcr_test::drawGreyTemplate());
  const cv::Mat scan = part.scanImage();
  cv::Mat canny;
  cv::Canny(scan, canny, 60, 150, 3, true);
  const cv::Mat to_canny = distanceTo(canny);

  // Every model point lies within 1 px of Canny's edges ...
  cv::Mat model = cv::Mat::zeros(scan.size(), CV_8UC1);
  int far_from_canny = 0;
  for (const amcr::OutlinePoint& o : part.outline())
  {
    far_from_canny += distanceToEdges(to_canny, o.position) > 1.0 ? 1 : 0;
    model.at<std::uint8_t>(std::clamp(cvRound(o.position.y), 0, scan.rows - 1),
                           std::clamp(cvRound(o.position.x), 0, scan.cols - 1)) = 255;
  }
  EXPECT_EQ(far_from_canny, 0) << "of " << part.outline().size() << " model points";
  // ... and Canny's edges are covered by the model (one point per 2 px), within 1 px of one.
  const cv::Mat to_model = distanceTo(model);
  std::vector<cv::Point> canny_points;
  cv::findNonZero(canny, canny_points);
  int uncovered = 0;
  for (const cv::Point& c : canny_points)
    uncovered += to_model.at<float>(c) > 1.5f ? 1 : 0;
  EXPECT_LE(uncovered, static_cast<int>(0.02 * canny_points.size())) << "of " << canny_points.size();

  // The disc's and the bar's edges are in the model, with normals towards
  // rising grey: out of the dark body into the light disc, i.e. inwards.
  const cv::Matx23d& to_table = part.originalToTable();
  const cv::Point2d disc_centre(to_table(0, 0) * 58 + to_table(0, 2), to_table(1, 1) * 58 + to_table(1, 2));
  const double disc_radius = 22 * to_table(0, 0);
  int on_disc = 0, inwards = 0;
  for (const amcr::OutlinePoint& o : part.outline())
  {
    const cv::Point2d r = cv::Point2d(o.position) - disc_centre;
    if (std::abs(cv::norm(r) - disc_radius) > 1.5)
      continue;
    ++on_disc;
    inwards += (r.x * o.normal.x + r.y * o.normal.y) < 0 ? 1 : 0;
  }
  EXPECT_GE(on_disc, static_cast<int>(0.8 * 2 * M_PI * disc_radius / 2)) << "model points on the disc's edge";
  EXPECT_EQ(inwards, on_disc) << "normals towards rising grey";
}

TEST(EdgeModel, TemplateTableIsAScanOfItsGreyImage)
{
  const amcr::Prototype part = templatePrototype(amcr_test::drawGreyTemplate());
  const cv::Mat scan = part.scanImage();
  // Longer than the table holds; an edge near the table's limit (127 px) may fall on either side of it.
  const amcr::RadialScanner reference(scan, amcr::EdgeThresholds(scan, kThreshold, kFullStrength), 1000.0);
  long compared = 0, mismatched = 0;
  for (int y = 0; y < part.height(); y += 7)
    for (int x = 0; x < part.width(); x += 7)
      for (int bin = 0; bin < amcr::kDirectionBins; bin += 3)
      {
        const amcr::RayHit hit = reference.scanAngle(static_cast<float>(x), static_cast<float>(y), amcr::binToAngle(bin));
        const float table = part.distance(x, y, bin);
        if (hit.valid && hit.distance > 126.f)
          continue;
        ++compared;
        if (hit.valid != (table >= 0.f) || (hit.valid && std::abs(hit.distance - table) > 0.5f))
          ++mismatched;
      }
  EXPECT_EQ(mismatched, 0) << "of " << compared << " rays";
  // Rays from inside the body meet the disc: the inner edges are in the table.
  const cv::Matx23d& to_table = part.originalToTable();
  const int x = cvRound(to_table(0, 0) * 58 + to_table(0, 2)), y = cvRound(to_table(1, 1) * 58 + to_table(1, 2));
  const float to_disc = part.distance(x, y, 0);
  EXPECT_NEAR(to_disc, 22 * to_table(0, 0), 1.5) << "from the disc's centre to its edge";
}

TEST(EdgeModel, AlphaChannelIsTheObjectsRegion)
{
  cv::Mat grey = amcr_test::drawGreyTemplate(), bgra;
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  // A printed frame around the body that the alpha channel leaves out.
  cv::rectangle(bgra, cv::Rect(4, 4, 152, 152), cv::Scalar(0, 0, 0, 255), 3);
  std::vector<cv::Mat> channels;
  cv::split(bgra, channels);
  channels[3].setTo(0);
  channels[3](amcr_test::kTemplateBody).setTo(255);
  cv::merge(channels, bgra);
  const amcr::Prototype part = templatePrototype(bgra);
  ASSERT_TRUE(part.isTemplate());
  // The body fills the table (its longer side is the prototype size) ...
  std::vector<cv::Point> inside;
  cv::findNonZero(part.mask(), inside);
  const cv::Rect box = cv::boundingRect(inside);
  EXPECT_NEAR(box.width, kSize, 1);
  EXPECT_NEAR(box.height, kSize, 1);
  // ... and no model point lies on the frame outside it.
  for (const amcr::OutlinePoint& o : part.outline())
  {
    ASSERT_GE(o.position.x, box.x - 3);
    ASSERT_LE(o.position.x, box.br().x + 2);
  }
  EXPECT_NEAR(part.originalToTable()(0, 0), static_cast<double>(kSize) / amcr_test::kTemplateBody.width, 0.01);
  // An alpha channel opaque everywhere is no region: the whole image is the template.
  channels[3].setTo(255);
  cv::merge(channels, bgra);
  EXPECT_NEAR(templatePrototype(bgra).originalToTable()(0, 0), static_cast<double>(kSize) / amcr_test::kTemplateSide, 0.01);
}

TEST(EdgeModel, BytesGiveTheSameTemplateBack)
{
  const amcr::Prototype part = templatePrototype(amcr_test::drawGreyTemplate());
  const std::vector<std::uint8_t> bytes = part.toBytes();
  const auto back = amcr::Prototype::fromBytes("part", bytes.data(), bytes.size());
  ASSERT_TRUE(back->isTemplate());
  EXPECT_EQ(cv::countNonZero(back->scanImage() != part.scanImage()), 0);
  EXPECT_EQ(cv::countNonZero(back->mask() != part.mask()), 0);
  ASSERT_EQ(back->outline().size(), part.outline().size());
  EXPECT_EQ(back->toBytes(), bytes);
  EXPECT_EQ(back->polarity(), 0) << "either polarity counts by default";

  const amcr::Prototype keeping("part", amcr_test::drawGreyTemplate(), kSize, kThreshold, 1.0, 1, "", kFullStrength,
                                true);
  EXPECT_EQ(keeping.polarity(), 1);
  const std::vector<std::uint8_t> kept = keeping.toBytes();
  EXPECT_EQ(amcr::Prototype::fromBytes("part", kept.data(), kept.size())->polarity(), 1);
  // A silhouette has no polarity of its own, whatever keep_polarity says.
  EXPECT_EQ(amcr::Prototype("star", amcr_test::drawPrototype(ShapeId::kStar), kSize, kThreshold, 1.0, 1, "", 0.0, true)
                .polarity(),
            0);
}

TEST(EdgeModel, TemplateWithoutEdgesIsRefusedByName)
{
  // A slow ramp: every grey level from 100 to 130, not a silhouette, and no step anywhere near an edge.
  cv::Mat faint(100, 100, CV_8UC1);
  for (int x = 0; x < faint.cols; ++x)
    faint.col(x).setTo(100 + 30 * x / (faint.cols - 1));
  try
  {
    amcr::Prototype("faint", faint, kSize, kThreshold, 1.0, 1, "", 0.0);
    FAIL() << "a template without edges was accepted";
  }
  catch (const amcr::MemoryError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'faint' is read as a grey template"), std::string::npos) << e.what();
  }
}

TEST(EdgeModel, PictureMarksEveryModelPoint)
{
  const amcr::Prototype part = templatePrototype(amcr_test::drawGreyTemplate());
  const int scale = 3;
  const cv::Mat picture = amcr::drawEdgeModel(part, scale);
  ASSERT_EQ(picture.size(), cv::Size(part.width() * scale, part.height() * scale));
  int marked = 0;
  for (const amcr::OutlinePoint& o : part.outline())
  {
    const cv::Vec3b c = picture.at<cv::Vec3b>(cvRound((o.position.y + 0.5) * scale), cvRound((o.position.x + 0.5) * scale));
    marked += (c[2] > 150 && c[0] < 100) ? 1 : 0;  // red
  }
  EXPECT_EQ(marked, static_cast<int>(part.outline().size()));
}
