// The turns of a prototype onto itself (self_similar_turns.h): found for a
// square face with a ring of dots a little off its centre (the cube's face of
// the real camera), not for shapes no turn repeats.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "amcr/memory/self_similar_turns.h"

namespace
{
constexpr int kSize = 128;             // prototype_size
constexpr double kEdgeThreshold = 40;  // the defaults' edge_threshold and edge_full_strength
constexpr double kFullStrength = 100;

/// A grey template: a dark square face on a grey board with a ring of 12
/// light dots (the border of a 4 x 4 grid), shifted towards the top left.
cv::Mat ringOfDots()
{
  cv::Mat image(160, 160, CV_8UC1, cv::Scalar(150));
  cv::rectangle(image, cv::Point(20, 20), cv::Point(139, 139), cv::Scalar(45), cv::FILLED);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (i == 0 || i == 3 || j == 0 || j == 3)
        cv::circle(image, cv::Point(34 + 30 * i, 32 + 30 * j), 6, cv::Scalar(215), cv::FILLED);
  return image;
}

cv::Mat silhouette(const std::vector<cv::Point>& polygon)
{
  cv::Mat image = cv::Mat::zeros(160, 160, CV_8UC1);
  cv::fillPoly(image, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(255));
  return image;
}

amcr::Prototype prototype(const cv::Mat& image)
{
  return amcr::Prototype("shape", image, kSize, kEdgeThreshold, 1.0, 1, "", kFullStrength);
}

bool holds(const std::vector<amcr::Affine>& turns, const amcr::Affine& turn)
{
  for (const amcr::Affine& t : turns)
    if (cv::norm(cv::Matx<double, 2, 3>(t - turn)) < 1e-9)
      return true;
  return false;
}
}  // namespace

TEST(SelfSimilarTurns, TurnIsARotationAboutTheModelCentre)
{
  const amcr::Prototype p = prototype(ringOfDots());
  amcr::Affine quarter, half;
  ASSERT_TRUE(amcr::modelTurn(p, 90, quarter));
  ASSERT_TRUE(amcr::modelTurn(p, 180, half));
  // Twice a quarter turn is the half turn; the turn keeps lengths.
  const amcr::Affine twice = amcr::composeAffine(quarter, quarter);
  EXPECT_LT(cv::norm(cv::Matx<double, 2, 3>(twice - half)), 1e-9);
  const cv::Point2d a = amcr::applyAffine(quarter, {10, 20}), b = amcr::applyAffine(quarter, {50, 80});
  EXPECT_NEAR(cv::norm(a - b), std::hypot(40.0, 60.0), 1e-9);
}

TEST(SelfSimilarTurns, RingOfDotsRepeatsUnderItsQuarterTurns)
{
  const amcr::Prototype p = prototype(ringOfDots());
  ASSERT_TRUE(p.isTemplate());
  const std::vector<amcr::Affine> turns = amcr::selfSimilarTurns(p);
  for (int degrees : {90, 180, 270})
  {
    amcr::Affine turn;
    ASSERT_TRUE(amcr::modelTurn(p, degrees, turn));
    EXPECT_TRUE(holds(turns, turn)) << degrees << " degrees: share "
                                    << amcr::modelRepeatShare(p, turn, 0.03 * kSize);
  }
  for (int degrees : {60, 120})
  {
    amcr::Affine turn;
    ASSERT_TRUE(amcr::modelTurn(p, degrees, turn));
    EXPECT_FALSE(holds(turns, turn)) << degrees << " degrees";
  }
}

TEST(SelfSimilarTurns, ShapesNoTurnRepeatsHaveNone)
{
  const cv::Mat ell = silhouette({{20, 20}, {60, 20}, {60, 100}, {140, 100}, {140, 140}, {20, 140}});
  const cv::Mat arrow = silhouette({{20, 80}, {90, 20}, {90, 55}, {140, 55}, {140, 105}, {90, 105}, {90, 140}});
  EXPECT_TRUE(amcr::selfSimilarTurns(prototype(ell)).empty());
  EXPECT_TRUE(amcr::selfSimilarTurns(prototype(arrow)).empty());
}

TEST(SelfSimilarTurns, ASquareRepeatsExactly)
{
  const amcr::Prototype p = prototype(silhouette({{30, 30}, {130, 30}, {130, 130}, {30, 130}}));
  amcr::Affine quarter;
  ASSERT_TRUE(amcr::modelTurn(p, 90, quarter));
  EXPECT_GT(amcr::modelRepeatShare(p, quarter, 1.5), 0.95);
  EXPECT_EQ(amcr::selfSimilarTurns(p).size(), 3u);  // 90, 180 and 270 degrees
}
