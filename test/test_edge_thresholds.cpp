// Edge thresholds relative to the local edge strength (edge_thresholds.h), on
// images drawn in code: a strong disc and a faint defocused one over a noisy
// background. The faint disc's outline must be an edge for the rays with the
// relative thresholds and not with the absolute one; the strong disc keeps
// the full threshold; flat noise never gives an edge.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/scan/edge_thresholds.h"
#include "amcr/base/errors.h"
#include "amcr/scan/radial_scan.h"

namespace
{
constexpr double kThreshold = 40.0;     // edge_threshold, grey levels
constexpr double kFullStrength = 100.0;  // edge_full_strength, grey levels
constexpr double kBackground = 180.0;
constexpr double kNoiseSigma = 3.0;      // grey levels, before the scan's blur
constexpr double kRadius = 40.0;         // px, both discs
// The faint disc's largest 2 px step: 40 grey levels blurred by 2 px, then by
// the scan's 1 px (2.24 px in all), times 2 Phi(1 / 2.24) - 1.
constexpr double kFaintStep = 13.8;
const cv::Point2f kStrongCentre(80, 120), kFaintCentre(400, 120), kFlatPoint(240, 320);

// 480 x 400: a disc 180 grey levels dark at kStrongCentre, one 40 grey levels
// dark and defocused (sigma 2 px) at kFaintCentre, noise, then the scan's blur
// (1 px).
cv::Mat drawnScanImage()
{
  cv::Mat image(400, 480, CV_32F, cv::Scalar(kBackground));
  cv::circle(image, kFaintCentre, static_cast<int>(kRadius), cv::Scalar(kBackground - 40), cv::FILLED, cv::LINE_AA);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 2.0);
  cv::circle(image, kStrongCentre, static_cast<int>(kRadius), cv::Scalar(0), cv::FILLED, cv::LINE_AA);
  cv::Mat noise(image.size(), CV_32F);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, kNoiseSigma);
  cv::Mat grey;
  cv::Mat(image + noise).convertTo(grey, CV_8U);
  return amcr::prepareScanImage(grey, 1.0);
}

// Rays from `centre` in 16 directions (at most 60 px): how many meet an edge
// within 2 px of kRadius, and how many meet any edge.
void countHits(const amcr::RadialScanner& scanner, const cv::Point2f& centre, int& on_outline, int& any)
{
  on_outline = any = 0;
  for (int k = 0; k < 16; ++k)
  {
    const amcr::RayHit hit = scanner.scanAngle(centre.x, centre.y, k * M_PI / 8);
    any += hit.valid;
    on_outline += hit.valid && std::abs(hit.distance - kRadius) <= 2.0;
  }
}

TEST(EdgeThresholds, FallWithTheLocalEdgeStrengthDownToTheNoiseFloor)
{
  const cv::Mat scan = drawnScanImage();
  const amcr::EdgeThresholds thresholds(scan, kThreshold, kFullStrength);
  // The 2 px steps of noise sigma 3 blurred by 1 px have a sigma of about 1
  // grey level (0.32 of the noise's).
  EXPECT_GT(thresholds.stepNoise(), 0.5);
  EXPECT_LT(thresholds.stepNoise(), 2.0);
  const double floor = amcr::EdgeThresholds::kNoiseSigmas * thresholds.stepNoise();
  // The strong disc: the full threshold on its outline (within the
  // interpolation to a weaker neighbouring tile).
  EXPECT_GE(thresholds.at(kStrongCentre.x + kRadius, kStrongCentre.y), 0.95 * kThreshold);
  EXPECT_LE(thresholds.at(kStrongCentre.x + kRadius, kStrongCentre.y), kThreshold);
  // The faint disc: 40 grey levels defocused by 2 px step by at most 14
  // over 2 px; its threshold lies below that, at the floor or above.
  const float faint = thresholds.at(kFaintCentre.x + kRadius, kFaintCentre.y);
  EXPECT_GE(faint, floor - 0.01);
  EXPECT_LE(faint, kFaintStep - 3.0);
  // Flat noise: the floor.
  EXPECT_NEAR(thresholds.at(kFlatPoint.x, kFlatPoint.y), floor, 0.01);
  EXPECT_NEAR(thresholds.lowest(), floor, 0.01);
}

TEST(EdgeThresholds, TheFaintOutlineIsAnEdgeOnlyRelativeToItsStrength)
{
  const cv::Mat scan = drawnScanImage();
  const amcr::RadialScanner relative(scan, amcr::EdgeThresholds(scan, kThreshold, kFullStrength), 60.0);
  const amcr::RadialScanner absolute(scan, amcr::EdgeThresholds(scan, kThreshold, 0.0), 60.0);
  int on_outline = 0, any = 0;
  countHits(relative, kFaintCentre, on_outline, any);
  EXPECT_EQ(on_outline, 16) << "relative thresholds: " << on_outline << " of 16 rays met the faint outline";
  countHits(absolute, kFaintCentre, on_outline, any);
  EXPECT_EQ(any, 0) << "the absolute threshold found " << any << " edges around the faint disc";
  // The strong disc is found either way, at the same place.
  countHits(relative, kStrongCentre, on_outline, any);
  EXPECT_EQ(on_outline, 16);
  // Flat noise: 16 rays of 60 px from 9 points meet nothing.
  int noise_hits = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
    {
      countHits(relative, kFlatPoint + cv::Point2f(20.f * dx, 10.f * dy), on_outline, any);
      noise_hits += any;
    }
  EXPECT_EQ(noise_hits, 0) << "rays in flat noise met edges";
}

TEST(EdgeThresholds, AnyPointGetsAThresholdOfTheFrame)
{
  // Points off the image, infinite or NaN (an outline mapped by a degenerate
  // transform) take the nearest tile's threshold, never one out of range.
  const cv::Mat scan = drawnScanImage();
  const amcr::EdgeThresholds thresholds(scan, kThreshold, kFullStrength);
  for (const float v : {-1e9f, -5.f, 1e9f, std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
  {
    const float t = thresholds.at(v, v);
    EXPECT_GE(t, thresholds.lowest()) << v;
    EXPECT_LE(t, kThreshold) << v;
  }
}

TEST(EdgeThresholds, UniformWhenFullStrengthIsZero)
{
  const cv::Mat scan = drawnScanImage();
  const amcr::EdgeThresholds thresholds(scan, kThreshold, 0.0);
  EXPECT_TRUE(thresholds.grid().empty());
  EXPECT_FLOAT_EQ(thresholds.at(kFaintCentre.x, kFaintCentre.y), kThreshold);
  EXPECT_FLOAT_EQ(thresholds.lowest(), kThreshold);
}

TEST(EdgeThresholds, StepNoiseOfPureNoise)
{
  // Unblurred Gaussian noise of sigma 4: the difference of two pixels has sigma 4 sqrt(2).
  cv::Mat noise(300, 400, CV_32F);
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::NORMAL, 128.0, 4.0);
  cv::Mat grey;
  noise.convertTo(grey, CV_8U);
  EXPECT_NEAR(amcr::stepNoiseSigma(grey), 4.0 * std::sqrt(2.0), 0.1 * 4.0 * std::sqrt(2.0));
}

TEST(EdgeThresholds, RefuseAnImageThatIsNotGrey)
{
  const cv::Mat colour(20, 20, CV_8UC3, cv::Scalar::all(100));
  try
  {
    amcr::EdgeThresholds thresholds(colour, kThreshold, kFullStrength);
    FAIL() << "a colour image was accepted";
  }
  catch (const amcr::InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("CV_8UC3"), std::string::npos) << e.what();
  }
}
}  // namespace
