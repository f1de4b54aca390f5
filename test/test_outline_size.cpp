// outlineSize (include/amcr/extraction/outline_fit.h): the size min_object_size is held
// against, the longer side of the smallest rotated rectangle around an
// outline, whatever the outline's rotation.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/extraction/outline_fit.h"

namespace
{
/// The outline of a w x h rectangle centred at `centre`, turned by `angle`, sampled every 1 px.
std::vector<cv::Point2d> rectangleOutline(double w, double h, double angle, cv::Point2d centre)
{
  std::vector<cv::Point2d> local;
  for (double x = -w / 2; x <= w / 2; x += 1.0)
  {
    local.emplace_back(x, -h / 2);
    local.emplace_back(x, h / 2);
  }
  for (double y = -h / 2; y <= h / 2; y += 1.0)
  {
    local.emplace_back(-w / 2, y);
    local.emplace_back(w / 2, y);
  }
  std::vector<cv::Point2d> out;
  const double c = std::cos(angle), s = std::sin(angle);
  for (const auto& p : local)
    out.emplace_back(centre.x + c * p.x - s * p.y, centre.y + s * p.x + c * p.y);
  return out;
}
}  // namespace

TEST(OutlineSize, IsTheLongerSideWhateverTheRotation)
{
  for (double angle : {0.0, 0.3, M_PI / 4, 2.0, -1.2})
  {
    EXPECT_NEAR(amcr::outlineSize(rectangleOutline(80, 30, angle, {200, 150})), 80.0, 0.05) << "angle " << angle;
    EXPECT_NEAR(amcr::outlineSize(rectangleOutline(20, 50, angle, {10, 400})), 50.0, 0.05) << "angle " << angle;
  }
}

TEST(OutlineSize, FewerThanTwoPointsHaveNoSize)
{
  EXPECT_EQ(amcr::outlineSize({}), 0.0);
  EXPECT_EQ(amcr::outlineSize({{12.0, 7.0}}), 0.0);
  EXPECT_NEAR(amcr::outlineSize({{0.0, 0.0}, {30.0, 40.0}}), 50.0, 1e-3);
}
