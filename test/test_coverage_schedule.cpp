// Coverage by construction (coverage_schedule.h): K frames read every
// lattice cell once, each frame's share is spread over the whole image, the
// rounds read new places, held objects are skipped, and bad settings are
// refused with the setting named.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/extraction/coverage_schedule.h"

namespace
{
const cv::Size kImage(640, 480);
constexpr double kSpacing = 20.0;

/// The lattice cell of a place (the round's offset is below a cell).
std::pair<int, int> cellOf(const amcr::RayPlace& p)
{
  return {static_cast<int>(std::floor(p.x / kSpacing)), static_cast<int>(std::floor(p.y / kSpacing))};
}

TEST(CoverageSchedule, KFramesReadEveryCellOnce)
{
  for (int frames : {1, 2, 4, 5})
  {
    std::set<std::pair<int, int>> seen;
    std::size_t count = 0;
    for (int f = 0; f < frames; ++f)
      for (const amcr::RayPlace& p : amcr::coveragePlaces(kImage, kSpacing, frames, f))
      {
        seen.insert(cellOf(p));
        ++count;
      }
    // 32 x 24 cells; the round's offset may push a last column or row's place off the image.
    EXPECT_EQ(count, seen.size()) << frames << " frames: a cell read twice";
    EXPECT_GE(seen.size(), 31u * 23u) << frames << " frames";
    EXPECT_LE(seen.size(), 32u * 24u) << frames << " frames";
  }
}

TEST(CoverageSchedule, EachFramesShareSpreadsOverTheImage)
{
  constexpr int kFrames = 4;
  for (int f = 0; f < kFrames; ++f)
  {
    const std::vector<amcr::RayPlace> places = amcr::coveragePlaces(kImage, kSpacing, kFrames, f);
    EXPECT_NEAR(static_cast<double>(places.size()), 32.0 * 24.0 / kFrames, 32.0 * 24.0 / kFrames * 0.1);
    // Every point of the image lies within 2.5 cells of one of the frame's places
    // (a band of the image read per frame would leave gaps of many cells).
    double largest_gap = 0.0;
    for (int y = 0; y < kImage.height; y += 5)
      for (int x = 0; x < kImage.width; x += 5)
      {
        double nearest = 1e9;
        for (const amcr::RayPlace& p : places)
          nearest = std::min(nearest, std::hypot(static_cast<double>(p.x) - x, static_cast<double>(p.y) - y));
        largest_gap = std::max(largest_gap, nearest);
      }
    EXPECT_LE(largest_gap, 2.5 * kSpacing) << "frame " << f;
  }
}

TEST(CoverageSchedule, TheNextRoundReadsNewPlacesAndHeadings)
{
  const std::vector<amcr::RayPlace> first = amcr::coveragePlaces(kImage, kSpacing, 4, 1);
  const std::vector<amcr::RayPlace> again = amcr::coveragePlaces(kImage, kSpacing, 4, 1);
  const std::vector<amcr::RayPlace> next = amcr::coveragePlaces(kImage, kSpacing, 4, 5);
  ASSERT_FALSE(first.empty());
  ASSERT_EQ(first.size(), again.size());
  EXPECT_EQ(first[0].x, again[0].x);  // a frame's places are a function of the frame
  EXPECT_EQ(first[0].theta, again[0].theta);
  const bool moved = first[0].x != next[0].x || first[0].y != next[0].y;
  EXPECT_TRUE(moved);
  EXPECT_NE(first[0].theta, next[0].theta);
}

TEST(CoverageSchedule, HeldObjectsAreSkipped)
{
  const std::vector<std::vector<cv::Point2f>> held = {{{100, 100}, {300, 100}, {300, 250}, {100, 250}}};
  std::size_t all = 0, kept = 0;
  for (int f = 0; f < 4; ++f)
  {
    all += amcr::coveragePlaces(kImage, kSpacing, 4, f).size();
    for (const amcr::RayPlace& p : amcr::coveragePlaces(kImage, kSpacing, 4, f, held))
    {
      ++kept;
      EXPECT_FALSE(p.x >= 100 && p.x <= 300 && p.y >= 100 && p.y <= 250) << p.x << ", " << p.y;
    }
  }
  // The held box is 200 x 150 px: about 75 cells fewer.
  EXPECT_NEAR(static_cast<double>(all - kept), 75.0, 12.0);
}

TEST(CoverageSchedule, SpacingFollowsTheSmallestObject)
{
  EXPECT_DOUBLE_EQ(amcr::coverageSpacing(60.0), 20.0);
  EXPECT_DOUBLE_EQ(amcr::coverageSpacing(3.0), amcr::kMinCoverageSpacing);
}

TEST(CoverageSchedule, BadSettingsAreRefusedByName)
{
  try
  {
    amcr::coveragePlaces(kImage, 0.5, 4, 0);
    FAIL() << "a spacing below 1 px was accepted";
  }
  catch (const amcr::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find("spacing"), std::string::npos) << e.what();
  }
  try
  {
    amcr::coveragePlaces(kImage, kSpacing, 0, 0);
    FAIL() << "0 frames were accepted";
  }
  catch (const amcr::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find("frames"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(amcr::coveragePlaces(cv::Size(0, 0), kSpacing, 4, 0).empty());
}
}  // namespace
