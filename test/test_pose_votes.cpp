// Poses proposed by the image itself (pose_votes.h): a match of the index is
// a similarity pose, and on a drawn scene the places on an object pool their
// votes at its true pose, among the first pools, at two object sizes, on
// the scene's image and on one of 4x its pixels (reduced to the working
// resolution, as the recognizer reads it).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/extraction/coverage_schedule.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/pose_votes.h"
#include "amcr/scan/ray_directions.h"
#include "amcr/working_scale.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

constexpr int kFirstPools = 10;    // the true pose among this many pools (4 are fitted per frame)
constexpr int kFitFrames = 2;      // fits of a pool's pose: the frame's and the next one's
constexpr double kFitError = 3.0;  // working px: the fitted outline this near the truth on average

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

/// The mean distance (image px) between the prototype's outline points mapped by `a` and by `b`.
double meanOutlineDistance(const amcr::Prototype& p, const amcr::Affine& a, const amcr::Affine& b)
{
  double sum = 0.0;
  for (const amcr::OutlinePoint& o : p.outline())
    sum += cv::norm(amcr::applyAffine(a, cv::Point2d(o.position)) - amcr::applyAffine(b, cv::Point2d(o.position)));
  return p.outline().empty() ? HUGE_VAL : sum / static_cast<double>(p.outline().size());
}

struct PoseCase
{
  double scale;      ///< the arrow's scale in the scene, prototype px -> input px
  int image_factor;  ///< the scene's side in multiples of 640 x 480 (2: 4x the pixels)
};

void PrintTo(const PoseCase& c, std::ostream* os) { *os << "scale " << c.scale << ", " << c.image_factor << "x side"; }

class TruePose : public ::testing::TestWithParam<PoseCase>
{
};

// The candidate stage as the recognizer runs it: the input reduced to the
// working resolution, the whole coverage lattice of one round (every frame's
// share of the K frames), the votes pooled; the true prototype at its true
// place and pose must be among the first pools, mapped back to input px.
TEST_P(TruePose, IsAmongTheFirstPools)
{
  const PoseCase c = GetParam();
  const amcr::Params params;
  const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar}, params);
  const amcr::ProposalIndex index(*memory, params.index_stride);
  amcr_test::Scene scene;
  scene.size = cv::Size(640 * c.image_factor, 480 * c.image_factor);
  const double f = c.image_factor;
  const amcr::Affine truth =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), {300 * f, 250 * f}, 0.5, c.scale * f, c.scale * f, 0.0);
  scene.objects.push_back({ShapeId::kArrow, truth});
  scene.clutter.seed = 7;
  const cv::Mat image = amcr_test::renderClean(scene);
  const amcr::WorkingScale working = amcr::chooseWorkingScale(image.size(), params.working_resolution);
  const amcr::RadialScanner scanner(amcr::prepareScanImage(amcr::toWorkingImage(image, working), params.blur_sigma),
                                    params.edge_threshold, params.max_ray_length);
  std::vector<amcr::RayPlace> places;
  const double spacing = amcr::coverageSpacing(params.min_object_size);
  for (int frame = 0; frame < params.coverage_frames; ++frame)
  {
    const std::vector<amcr::RayPlace> share = amcr::coveragePlaces(working.working, spacing, params.coverage_frames, frame);
    places.insert(places.end(), share.begin(), share.end());
  }
  const std::vector<amcr::PoseVote> pools = amcr::poolPoseVotes(index, *memory, scanner, places, 3);
  ASSERT_FALSE(pools.empty());
  const amcr::Prototype& arrow = (*memory)[0];
  const amcr::Affine true_table_to_input = amcr::composeAffine(arrow.tableToOriginal(), truth);
  // A pool is the true pose when the fits it starts put the outline on the
  // truth: a vote's pose is a similarity whose heading and scale the index
  // quantizes (up to 8 px off on average for the larger arrow), refined on
  // the edges by the fit of the frame that starts from it and by the next
  // frame's, from the leading hypothesis it injects.
  const amcr::Affine true_table_to_working = amcr::composeAffine(true_table_to_input, working.toWorking());
  int found = -1;
  double error = 0.0;
  for (int k = 0; k < std::min(kFirstPools, static_cast<int>(pools.size())) && found < 0; ++k)
  {
    if (pools[k].prototype != 0)
      continue;
    amcr::Affine fitted = pools[k].table_to_image;
    for (int frame = 0; frame < kFitFrames; ++frame)
      fitted = amcr::refineOnEdges(arrow, scanner, fitted, params.refine_iterations, params.refine_search);
    error = meanOutlineDistance(arrow, fitted, true_table_to_working);
    if (error <= kFitError)
      found = k;
  }
  std::cout << "[ votes    ] scale " << c.scale << " on " << image.cols << " x " << image.rows << ": the true pose is pool "
            << found << " of " << pools.size()
            << (found >= 0 ? " with " + std::to_string(pools[found].places.size()) + " votes, its fit " +
                                 std::to_string(error) + " working px off on average once fitted"
                           : std::string())
            << "\n";
  EXPECT_TRUE(found >= 0 && found < kFirstPools)
      << "scale " << c.scale << " on " << image.cols << " x " << image.rows << ": the arrow's pose is not among the first "
      << kFirstPools << " pools (first: prototype " << pools[0].prototype << ", " << pools[0].places.size() << " votes)";
  if (found >= 0)
  {
    EXPECT_GE(pools[found].places.size(), 2u) << "one place alone is no pool";
  }
}

INSTANTIATE_TEST_SUITE_P(TwoSizesTwoImages, TruePose,
                         ::testing::Values(PoseCase{0.6, 1}, PoseCase{1.1, 1}, PoseCase{0.6, 2}, PoseCase{1.1, 2}));
}  // namespace
