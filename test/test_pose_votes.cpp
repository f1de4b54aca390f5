// Poses proposed by the image itself (pose_votes.h): a match of the index is
// a similarity pose, and on a drawn scene the places on an object pool their
// votes at its true pose, among the first pools, at two object sizes.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/pose_votes.h"
#include "amcr/scan/ray_directions.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kFirstPools = 10;        // the true pose among this many pools (4 are fitted per frame)
constexpr double kCornerShare = 0.08;  // of the object's size: a pool's pose this near the truth at every corner

TEST(PoseVotes, AMatchPutsItsTablePointUnderThePlace)
{
  amcr::ProposalCandidate c;
  c.prototype = 0;
  c.x = 50.f;
  c.y = 60.f;
  c.bin = 9;                                      // the match's heading: 9 bins
  c.log_scale = static_cast<float>(std::log(2.0));  // 2 table px per image px
  const amcr::RayPlace place{100.f, 80.f, 0.5f};
  const amcr::Affine a = amcr::matchPose(c, place);
  const cv::Point2d at = amcr::applyAffine(a, {50, 60});
  EXPECT_NEAR(at.x, 100.0, 1e-9);
  EXPECT_NEAR(at.y, 80.0, 1e-9);
  // The table direction of the match's heading points along the place's heading, at half the length.
  const double heading = amcr::binToAngle(9);
  const cv::Point2d ahead = amcr::applyAffine(a, {50 + 10 * std::cos(heading), 60 + 10 * std::sin(heading)}) - at;
  EXPECT_NEAR(ahead.x, 5 * std::cos(0.5), 1e-6);  // log_scale is a float
  EXPECT_NEAR(ahead.y, 5 * std::sin(0.5), 1e-6);
}

/// The worst distance (image px) between the prototype's table box corners mapped by `a` and by `b`.
double worstCorner(const amcr::Prototype& p, const amcr::Affine& a, const amcr::Affine& b)
{
  const cv::Rect box = cv::boundingRect(p.mask());
  double worst = 0.0;
  for (const cv::Point2d& c : {cv::Point2d(box.x, box.y), cv::Point2d(box.br().x, box.y),
                               cv::Point2d(box.br().x, box.br().y), cv::Point2d(box.x, box.br().y)})
    worst = std::max(worst, cv::norm(amcr::applyAffine(a, c) - amcr::applyAffine(b, c)));
  return worst;
}

class TruePose : public ::testing::TestWithParam<double>
{
};

TEST_P(TruePose, IsAmongTheFirstPools)
{
  const double scale = GetParam();
  const amcr::Params params;
  const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, params);
  const amcr::ProposalIndex index(*memory, params.index_stride);
  amcr_test::Scene scene;
  const amcr::Affine truth = amcr_test::makeAffine(amcr_test::prototypeCentre(), {300, 250}, 0.5, scale, scale, 0.0);
  scene.objects.push_back({ShapeId::kArrow, truth});
  scene.clutter.seed = 7;
  const cv::Mat image = amcr_test::renderClean(scene);
  const amcr::RadialScanner scanner(amcr::prepareScanImage(image, params.blur_sigma), params.edge_threshold,
                                    params.max_ray_length);
  // Places on a 12 px grid over the whole image, heading 0: the object's and the clutter's.
  std::vector<amcr::RayPlace> places;
  for (int y = 6; y < image.rows; y += 12)
    for (int x = 6; x < image.cols; x += 12)
      places.push_back({static_cast<float>(x), static_cast<float>(y), 0.f});
  const std::vector<amcr::PoseVote> pools = amcr::poolPoseVotes(index, *memory, scanner, places, 3);
  ASSERT_FALSE(pools.empty());
  const amcr::Prototype& arrow = (*memory)[0];
  const amcr::Affine true_table_to_image = amcr::composeAffine(arrow.tableToOriginal(), truth);
  const double size = 200.0 * scale;  // the prototype image's side in the scene, px
  int found = -1;
  for (int k = 0; k < static_cast<int>(pools.size()) && found < 0; ++k)
  {
    if (pools[k].prototype == 0 && worstCorner(arrow, pools[k].table_to_image, true_table_to_image) <= kCornerShare * size)
      found = k;
  }
  std::cout << "[ votes    ] scale " << scale << ": the true pose is pool " << found << " of " << pools.size()
            << (found >= 0 ? " with " + std::to_string(pools[found].places.size()) + " votes" : std::string()) << "\n";
  EXPECT_TRUE(found >= 0 && found < kFirstPools) << "scale " << scale << ": the arrow's pose is not among the first " << kFirstPools
                      << " pools (first: prototype " << pools[0].prototype << ", " << pools[0].places.size() << " votes)";
  if (found >= 0)
  {
    EXPECT_GE(pools[found].places.size(), 2u) << "one place alone is no pool";
  }
}

INSTANTIATE_TEST_SUITE_P(TwoSizes, TruePose, ::testing::Values(0.6, 1.1));
}  // namespace
