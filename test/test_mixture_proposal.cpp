// The mixture proposal of new M-particles (particle_filter.cpp, seedM): a
// share drawn at the proposal index's places, the rest uniformly, each with
// the importance weight pi / q. On a toy problem whose target is known (the
// seeding prior pi itself: a prototype from the context prior, a position
// uniform over its interior), the weighted particles must reproduce pi's
// moments although the proposal q is far from it; with the index off every
// weight is 1, as before the index; proposal_correction c weighs by (pi / q)^c,
// so that with 0 (sensor resetting) a proposed particle is weighed as a
// uniform one.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/filter/particle_filter.h"
#include "amcr/scan/radial_scan.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

struct Moments
{
  double weight = 0.0, x = 0.0, y = 0.0, xx = 0.0, yy = 0.0;
  void add(double w, double px, double py)
  {
    weight += w;
    x += w * px;
    y += w * py;
    xx += w * px * px;
    yy += w * py * py;
  }
  double meanX() const { return x / weight; }
  double meanY() const { return y / weight; }
  double sdX() const { return std::sqrt(xx / weight - meanX() * meanX()); }
  double sdY() const { return std::sqrt(yy / weight - meanY() * meanY()); }
};

/// The largest difference of mean or spread (x or y) between `a` and `b`, over both prototypes.
double worstMomentError(const Moments (&a)[2], const Moments (&b)[2])
{
  double worst = 0.0;
  for (int q = 0; q < 2; ++q)
    worst = std::max({worst, std::abs(a[q].meanX() - b[q].meanX()), std::abs(a[q].meanY() - b[q].meanY()),
                      std::abs(a[q].sdX() - b[q].sdX()), std::abs(a[q].sdY() - b[q].sdY())});
  return worst;
}

amcr::Params toyParams()
{
  amcr::Params p;
  p.num_v_particles = 1;  // one V-particle: the index's places are a few, far from uniform
  p.m_particles_per_v = 40000;
  p.min_support = 1;
  p.kld_error = 0.0;
  p.index_share = 0.5;
  p.proposal_correction = 1.0;  // exact importance sampling: the weights are pi / q
  p.prototype_priors = {{"arrow", 3.0}, {"crescent", 1.0}};  // pi: 3/4 arrow, 1/4 crescent
  p.seed = 3;
  return p;
}

/// The arrow, large, on a plain background: most V-particles seeded inside
/// it see an edge on all 8 rays, so the index proposes.
amcr::RadialScanner toyScene(const amcr::Params& p, cv::Mat& storage)
{
  cv::Mat image(480, 640, CV_8UC1, cv::Scalar(30));
  const amcr::Affine to_image =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.4, 1.6, 1.6, 0.0);
  amcr_test::fillPolygon(image, amcr_test::transformPoints(to_image, amcr_test::shapePolygon(ShapeId::kArrow)), 220);
  storage = amcr::prepareScanImage(image, p.blur_sigma);
  return amcr::RadialScanner(storage, p.edge_threshold, p.max_ray_length);
}

/// The toy filter of `p`, seeded until its V-particle lands where all 8 rays
/// meet an edge (else the index has nothing to propose and the toy tests nothing).
std::unique_ptr<amcr::ParticleFilter> seededToy(const amcr::Params& p, const amcr::RadialScanner& scanner)
{
  static const auto memory = amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent});
  auto filter = std::make_unique<amcr::ParticleFilter>(p, memory);
  for (int attempt = 0; attempt < 20; ++attempt)
  {
    filter->seed(scanner);
    if (filter->vParticles()[0].rays.valid_rays() == amcr::kFeatureRays)
      break;
  }
  return filter;
}

TEST(MixtureProposal, WeightedNewParticlesFollowTheSeedingPrior)
{
  const amcr::Params p = toyParams();
  cv::Mat storage;
  const amcr::RadialScanner scanner = toyScene(p, storage);
  const std::unique_ptr<amcr::ParticleFilter> toy = seededToy(p, scanner);
  const amcr::ParticleFilter& filter = *toy;
  const amcr::PrototypeMemory* memory = &filter.memory();
  ASSERT_NE(filter.proposalIndex(), nullptr);
  const amcr::MParticleSet& m = filter.mParticles();

  // pi's moments: the prior over prototypes, the interior's centroid and spread.
  const double prior[2] = {0.75, 0.25};
  Moments truth[2], weighted[2], unweighted[2];
  for (int q = 0; q < 2; ++q)
    for (const cv::Point& at : (*memory)[q].interior())
      truth[q].add(1.0, at.x, at.y);
  int from_index = 0;
  for (std::size_t i = 0; i < m.size(); ++i)
  {
    weighted[m.prototype[i]].add(std::exp(m.log_proposal[i]), m.x[i], m.y[i]);
    unweighted[m.prototype[i]].add(1.0, m.x[i], m.y[i]);
    from_index += m.log_proposal[i] < -1.0f ? 1 : 0;  // weight well below 1: drawn near a place
  }
  ASSERT_GT(from_index, static_cast<int>(m.size() / 10)) << "the index proposed too little to test";

  const double total = weighted[0].weight + weighted[1].weight;
  const double unweighted_arrow = unweighted[0].weight / (unweighted[0].weight + unweighted[1].weight);
  EXPECT_NEAR(weighted[0].weight / total, prior[0], 0.02) << "unweighted " << unweighted_arrow;
  // The proposal alone is far from pi (so that the test can fail): its
  // particles crowd at the index's places.
  const double worst_unweighted = worstMomentError(unweighted, truth);
  EXPECT_GT(worst_unweighted, 4.0);
  const double worst_weighted = worstMomentError(weighted, truth);
  std::cout << "[ mixture  ] " << from_index << " of " << m.size() << " particles from the index; arrow share "
            << unweighted_arrow << " unweighted, " << weighted[0].weight / total << " weighted (prior 0.75); worst "
            << "moment error " << worst_unweighted << " px unweighted, " << worst_weighted << " px weighted" << std::endl;
  // Tolerance: a few standard errors of ~10^4 uniform samples (the table
  // spread is ~25-35 px, so the standard error of a mean is ~0.3-0.5 px).
  // [measured: 0.54 px at worst; the unweighted particles 27 px]
  EXPECT_LT(worst_weighted, 1.5);
}

TEST(MixtureProposal, TheCorrectionIsAnExponentOfTheImportanceWeight)
{
  // The same seed draws the same particles whatever the correction; only their weights differ.
  amcr::Params p = toyParams();
  cv::Mat storage;
  const amcr::RadialScanner scanner = toyScene(p, storage);
  const std::unique_ptr<amcr::ParticleFilter> exact = seededToy(p, scanner);
  p.proposal_correction = 0.5;
  const std::unique_ptr<amcr::ParticleFilter> half = seededToy(p, scanner);
  p.proposal_correction = 0.0;
  const std::unique_ptr<amcr::ParticleFilter> resetting = seededToy(p, scanner);
  const amcr::MParticleSet &e = exact->mParticles(), &h = half->mParticles(), &r = resetting->mParticles();
  ASSERT_EQ(e.size(), r.size());
  int weighted = 0;
  for (std::size_t i = 0; i < e.size(); ++i)
  {
    ASSERT_EQ(e.x[i], r.x[i]);
    ASSERT_EQ(e.prototype[i], h.prototype[i]);
    ASSERT_EQ(r.log_proposal[i], 0.f) << "sensor resetting weighs a proposed particle as a uniform one";
    ASSERT_NEAR(h.log_proposal[i], 0.5f * e.log_proposal[i], 1e-4f);
    weighted += e.log_proposal[i] < -1.0f ? 1 : 0;
  }
  EXPECT_GT(weighted, static_cast<int>(e.size() / 10)) << "the index proposed too little to test";
}

TEST(MixtureProposal, WithTheIndexOffEveryWeightIsOne)
{
  amcr::Params p = toyParams();
  p.index_share = 0.0;
  amcr::ParticleFilter filter(p, amcr_test::drawnMemory({ShapeId::kArrow, ShapeId::kCrescent}));
  EXPECT_EQ(filter.proposalIndex(), nullptr);
  cv::Mat storage;
  const amcr::RadialScanner scanner = toyScene(p, storage);
  filter.seed(scanner);
  for (int iteration = 0; iteration < 5; ++iteration)
    filter.update(0, scanner);
  for (float w : filter.mParticles().log_proposal)
    ASSERT_EQ(w, 0.f);
}
}  // namespace
