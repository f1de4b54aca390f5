// How the benchmark's baselines read a prototype (bench/baselines/prototype_image.h): as amcr does,
// a silhouette when it has two grey levels and no alpha channel short of opaque, else a grey
// template with its region; a silhouette's mask is its grey image as it was.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/memory/edge_model.h"
#include "baselines/prototype_image.h"
#include "scene_drawing.h"
#include "template_drawing.h"

namespace
{
TEST(PrototypeImage, SilhouetteKeepsItsMask)
{
  const cv::Mat star = amcr_test::drawPrototype(amcr_test::ShapeId::kStar);
  ASSERT_TRUE(amcr::isSilhouette(star));
  const amcr_bench::PrototypeImage p = amcr_bench::prototypeImage("star", star);
  EXPECT_FALSE(p.isTemplate());
  EXPECT_EQ(cv::countNonZero(p.mask != star), 0);
}

TEST(PrototypeImage, GreyImageIsATemplateOverTheWholeImage)
{
  const cv::Mat part = amcr_test::drawGreyTemplate();
  ASSERT_FALSE(amcr::isSilhouette(part));
  const amcr_bench::PrototypeImage p = amcr_bench::prototypeImage("part", part);
  ASSERT_TRUE(p.isTemplate());
  EXPECT_EQ(cv::countNonZero(p.grey != part), 0);
  EXPECT_EQ(cv::countNonZero(p.mask), static_cast<int>(part.total()));
}

// A two-level image with a transparent margin is a template (amcr reads it as one), its region the
// opaque pixels; an alpha channel opaque everywhere leaves a silhouette.
TEST(PrototypeImage, AlphaChannelMakesATemplate)
{
  const cv::Mat outline = amcr_test::drawTemplateOutline();
  cv::Mat alpha(outline.size(), CV_8UC1, cv::Scalar(0));
  alpha(cv::Rect(10, 10, 140, 140)).setTo(255);
  cv::Mat bgra;
  cv::merge(std::vector<cv::Mat>{outline, outline, outline, alpha}, bgra);
  const amcr_bench::PrototypeImage p = amcr_bench::prototypeImage("square", bgra);
  ASSERT_TRUE(p.isTemplate());
  EXPECT_EQ(cv::countNonZero(p.mask), 140 * 140);
  EXPECT_EQ(p.mask.at<unsigned char>(9, 9), 0);

  cv::merge(std::vector<cv::Mat>{outline, outline, outline, cv::Mat(outline.size(), CV_8UC1, cv::Scalar(255))}, bgra);
  EXPECT_FALSE(amcr_bench::prototypeImage("square", bgra).isTemplate());
}

TEST(PrototypeImage, FileOfATemplateKeepsItsAlphaAndAnUnreadableFileIsNamed)
{
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "amcr_test_prototype_image";
  std::filesystem::create_directories(dir);
  const cv::Mat part = amcr_test::drawGreyTemplate();
  cv::Mat alpha(part.size(), CV_8UC1, cv::Scalar(255));
  alpha.row(0).setTo(0);
  cv::Mat bgra;
  cv::merge(std::vector<cv::Mat>{part, part, part, alpha}, bgra);
  const std::string path = (dir / "part.png").string();
  ASSERT_TRUE(cv::imwrite(path, bgra));
  const amcr_bench::PrototypeImage p = amcr_bench::readPrototypeImage("part", path);
  ASSERT_TRUE(p.isTemplate());
  EXPECT_EQ(cv::countNonZero(p.grey != part), 0);
  EXPECT_EQ(cv::countNonZero(p.mask), static_cast<int>(part.total()) - part.cols);

  const std::string missing = (dir / "missing.png").string();
  try
  {
    amcr_bench::readPrototypeImage("missing", missing);
    ADD_FAILURE() << "a missing file was read";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}
}  // namespace
