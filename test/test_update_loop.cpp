// The fast update loop (blocks of M-particles in float lanes, bitwise the
// same output) against its plain references:
// ObservationModel::measure (blocks of M-particles in float lanes,
// observation_model_lanes.cpp) against measureReference (one M-particle at a
// time), and bestHeadingBin (every bin costed at once, heading_search.cpp)
// against bestHeadingBinReference. Both do the same float operations in the
// same order, so with GCC on x86-64 (no FMA contraction) the output is
// asserted bitwise equal; elsewhere within the tolerances below. A seeded
// sweep over the drawn prototypes: M-particles anywhere in their tables (at
// the borders too), any heading, both deviation spaces, both likelihood
// forms, V-particles with invalid rays and with triangles that are refused.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/affine.h"
#include "amcr/filter/corrected_scan.h"
#include "amcr/base/errors.h"
#include "amcr/filter/heading_proposal.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/filter/relational_update.h"
#include "scene_drawing.h"

namespace
{
using amcr::kFeatureRays;
using amcr::kTriangleRays;

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__FMA__)
constexpr bool kBitwise = true;  // the same SSE float operations in both paths
#else
constexpr bool kBitwise = false;  // FMA contraction may differ between the scalar and the vector code
#endif
constexpr double kLogLikelihoodTolerance = 1e-3;  // eq. 6, log units
constexpr double kAffineTolerance = 1e-4;         // A, relative to its largest entry (at least 1)

/// Why the reference refuses (or accepts) a relational particle: the cases the sweep must cover.
enum class Outcome
{
  kAccepted,
  kNoVTriangle,  ///< a V triangle ray met no edge
  kNoTableEdge,  ///< an M triangle ray met no edge
  kDegenerate,   ///< a triangle below min_triangle_area
  kMirrored,     ///< det B <= 0
  kOutOfScale,   ///< a singular value beyond max_affine_scale
  kCount
};

Outcome classify(const amcr::Params& p, const amcr::Prototype& prototype, const amcr::VRayEnds& v, float x, float y,
                 float theta)
{
  if (!v.triangle_valid)
    return Outcome::kNoVTriangle;
  const cv::Point at = amcr::nearestTablePixel(x, y);
  float tx[kTriangleRays], ty[kTriangleRays];
  if (!amcr::tableTriangle(prototype.rawDistances(at.x, at.y), at, amcr::angleToBin(theta), tx, ty))
    return Outcome::kNoTableEdge;
  const float area = static_cast<float>(p.min_triangle_area);
  float b[6];
  if (!amcr::affineFromTriangles(tx, ty, v.triangle_x, v.triangle_y, area, area, b))
    return Outcome::kDegenerate;
  if (b[0] * b[4] - b[1] * b[3] <= 0.f)
    return Outcome::kMirrored;
  if (!amcr::affineScaleAccepted(b, static_cast<float>(p.max_affine_scale)))
    return Outcome::kOutOfScale;
  return Outcome::kAccepted;
}

/// A V-particle's ray ends: what the table holds at (at, bin), scaled (past
/// max_affine_scale either way at times), with noise and invalid rays, or at
/// random; sometimes collapsed (a degenerate triangle) or mirrored. Three
/// rays of positive length at 0, 120 and 240 deg always span a triangle of
/// one orientation, so the mirrored ones take a negative length for the ray
/// at 120 deg: input no scan gives, to exercise the check.
amcr::VRayEnds randomVEnds(std::mt19937_64& gen, const amcr::Prototype& prototype, const cv::Point& at, int bin,
                           double max_scale)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  amcr::VParticle v;
  v.x = static_cast<float>(640 * unit(gen));
  v.y = static_cast<float>(480 * unit(gen));
  v.theta = static_cast<float>(2 * M_PI * unit(gen) - M_PI);
  const bool on_object = unit(gen) < 0.7;
  const double scale = std::exp((2 * unit(gen) - 1) * 1.3 * std::log(max_scale));
  const bool mirrored = unit(gen) < 0.15;
  const bool collapsed = unit(gen) < 0.1;  // all rays one length: a thin triangle
  const double invalid_share = unit(gen) < 0.5 ? 0.0 : 0.3;
  std::normal_distribution<double> noise(0.0, 3.0 * unit(gen));
  float distance[kFeatureRays + 2];
  bool valid[kFeatureRays + 2];
  for (int j = 0; j < kFeatureRays + 2; ++j)
  {
    const int ray = j < kFeatureRays ? j * amcr::kFeatureBinStep : (j - kFeatureRays + 1) * amcr::kTriangleBinStep;
    const float table_distance = prototype.distance(at.x, at.y, (bin + ray) % amcr::kDirectionBins);
    double d = 2 + 150 * unit(gen);
    if (on_object && table_distance > 0.f)
      d = std::max(0.5, scale * table_distance + noise(gen));
    if (collapsed)
      d = 1e-3;
    if (mirrored && j == kFeatureRays)
      d = -4 * d;
    distance[j] = static_cast<float>(d);
    valid[j] = unit(gen) >= invalid_share;
  }
  return amcr::rayEnds(v, distance, valid);
}

/// `count` M-particles: a third in a cloud around the first, a third on a
/// table border (the nearest pixel the first or last row or column), the
/// others anywhere in their tables.
amcr::MParticleSet randomMParticles(std::mt19937_64& gen, const amcr::PrototypeMemory& memory, int count)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  amcr::MParticleSet m;
  m.resize(count);
  for (int i = 0; i < count; ++i)
  {
    const int kind = i == 0 ? 2 : i % 3;
    m.prototype[i] = kind == 0 ? m.prototype[0] : static_cast<int>(gen() % memory.size());
    const amcr::Prototype& p = memory[m.prototype[i]];
    const float w = static_cast<float>(p.width()), h = static_cast<float>(p.height());
    m.x[i] = static_cast<float>(unit(gen) * (w - 0.02) - 0.49);
    m.y[i] = static_cast<float>(unit(gen) * (h - 0.02) - 0.49);
    m.theta[i] = static_cast<float>(4 * M_PI * unit(gen) - 2 * M_PI);
    if (kind == 0)
    {
      m.x[i] = std::min(std::max(m.x[0] + static_cast<float>(4 * unit(gen) - 2), 0.f), w - 1.f);
      m.y[i] = std::min(std::max(m.y[0] + static_cast<float>(4 * unit(gen) - 2), 0.f), h - 1.f);
      m.theta[i] = m.theta[0] + static_cast<float>(0.3 * unit(gen) - 0.15);
    }
    else if (kind == 1)
    {
      const float edge = static_cast<float>(0.49 * unit(gen));  // rounds onto the border pixel
      const int side = static_cast<int>(gen() % 4);
      if (side == 0)
        m.x[i] = -edge;
      else if (side == 1)
        m.x[i] = w - 1.f + edge;
      else if (side == 2)
        m.y[i] = -edge;
      else
        m.y[i] = h - 1.f + edge;
    }
    for (int e = 0; e < 6; ++e)  // what an update that refuses must leave alone
      m.affine[e][i] = static_cast<float>(e + i);
    m.affine_valid[i] = 7;
    m.log_likelihood[i] = 1.f;
  }
  return m;
}

std::string describe(const amcr::Params& p)
{
  std::ostringstream s;
  s << amcr::toString(p.deviation_space) << " space, " << amcr::toString(p.likelihood_form)
    << " form, min_triangle_area " << p.min_triangle_area << ", max_affine_scale " << p.max_affine_scale;
  return s.str();
}

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Fast and reference outputs of particle i agree (bitwise where kBitwise);
/// counts the bitwise-equal ones.
void expectSameParticle(const amcr::MParticleSet& fast, const amcr::MParticleSet& ref, std::size_t i,
                        const std::string& what, int& bitwise_equal)
{
  ASSERT_EQ(fast.affine_valid[i], ref.affine_valid[i]) << what << ", particle " << i;
  bool same = sameBits(fast.log_likelihood[i], ref.log_likelihood[i]);
  ASSERT_NEAR(fast.log_likelihood[i], ref.log_likelihood[i], kLogLikelihoodTolerance) << what << ", particle " << i;
  float largest = 1.f;
  for (int e = 0; e < 6; ++e)
    largest = std::max(largest, std::abs(ref.affine[e][i]));
  for (int e = 0; e < 6; ++e)
  {
    same = same && sameBits(fast.affine[e][i], ref.affine[e][i]);
    ASSERT_NEAR(fast.affine[e][i], ref.affine[e][i], kAffineTolerance * largest)
        << what << ", particle " << i << ", entry " << e;
  }
  if (kBitwise)
  {
    ASSERT_TRUE(same) << what << ", particle " << i << ": not bitwise equal";
  }
  bitwise_equal += same ? 1 : 0;
}

std::vector<amcr::Params> sweptParams()
{
  std::vector<amcr::Params> out;
  for (amcr::DeviationSpace space : {amcr::DeviationSpace::kImage, amcr::DeviationSpace::kPrototype})
    for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
      for (const std::pair<double, double>& limits :
           {std::make_pair(amcr::Params().min_triangle_area, amcr::Params().max_affine_scale),
            std::make_pair(20.0, 8.0), std::make_pair(150.0, 1.5)})
      {
        amcr::Params p;
        p.ray_correspondence = amcr::RayCorrespondence::kPaper;  // per-bin lookups: the block path
        p.deviation_space = space;
        p.likelihood_form = form;
        p.sigma_w = form == amcr::LikelihoodForm::kPaper ? 10.0 : 5.0;
        p.p_invalid = 0.07;
        p.min_triangle_area = limits.first;
        p.max_affine_scale = limits.second;
        out.push_back(p);
      }
  return out;
}

class UpdateLoop : public ::testing::Test
{
protected:
  static void SetUpTestSuite() { memory_ = amcr_test::drawnMemory(amcr_test::allShapes()); }
  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
};
std::shared_ptr<const amcr::PrototypeMemory> UpdateLoop::memory_;

TEST_F(UpdateLoop, MeasureEqualsMeasureReferenceOverASweep)
{
  std::mt19937_64 gen(20261216);
  for (const amcr::Params& p : sweptParams())
  {
    const amcr::ObservationModel model(p);
    int outcomes[static_cast<int>(Outcome::kCount)] = {};
    int particles = 0, compared = 0, bitwise_equal = 0;
    for (int trial = 0; trial < 150; ++trial)
    {
      // Counts that are not a multiple of the block, ranges that start inside one.
      const int count = 1 + static_cast<int>(gen() % 100);
      const std::size_t begin = gen() % 3 == 0 ? gen() % count : 0;
      const amcr::MParticleSet initial = randomMParticles(gen, *memory_, count);
      const cv::Point at0 = amcr::nearestTablePixel(initial.x[0], initial.y[0]);
      const amcr::VRayEnds v = randomVEnds(gen, (*memory_)[initial.prototype[0]], at0,
                                           amcr::angleToBin(initial.theta[0]), p.max_affine_scale);
      amcr::MParticleSet fast = initial, ref = initial;
      model.measure(*memory_, v, fast, begin, count);
      model.measureReference(*memory_, v, ref, begin, count);
      compared += count;
      for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i)
      {
        expectSameParticle(fast, ref, i, describe(p), bitwise_equal);
        if (HasFatalFailure())
          return;
        if (i < begin)
          continue;
        ++particles;
        const Outcome o = classify(p, (*memory_)[initial.prototype[i]], v, initial.x[i], initial.y[i],
                                   initial.theta[i]);
        ++outcomes[static_cast<int>(o)];
        ASSERT_EQ(fast.affine_valid[i] != 0, o == Outcome::kAccepted) << describe(p) << ", particle " << i;
      }
    }
    // Every outcome occurred, so each was compared.
    for (int o = 0; o < static_cast<int>(Outcome::kCount); ++o)
      EXPECT_GT(outcomes[o], 0) << describe(p) << ": outcome " << o << " never occurred";
    EXPECT_GE(outcomes[static_cast<int>(Outcome::kAccepted)], 10) << describe(p);
    if (kBitwise)
    {
      EXPECT_EQ(bitwise_equal, compared) << describe(p);
    }
  }
}

// ray_correspondence affine (the default): with no refits the block path
// reads the table along each M-particle's view shape and then along A
// (corrected_scan.h); with refits measure is measureReference. Frontal and
// oblique view shapes, both spaces and forms.
TEST_F(UpdateLoop, MeasureEqualsMeasureReferenceWithAffineCorrectedLookups)
{
  std::mt19937_64 gen(202612161);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const amcr::Params& swept : sweptParams())
    for (int refits : {0, 1})
    {
      amcr::Params p = swept;
      p.ray_correspondence = amcr::RayCorrespondence::kAffine;
      p.affine_refits = refits;
      const amcr::ObservationModel model(p);
      int compared = 0, accepted = 0, refused = 0, bitwise_equal = 0;
      for (int trial = 0; trial < 100; ++trial)
      {
        const int count = 1 + static_cast<int>(gen() % 100);
        amcr::MParticleSet initial = randomMParticles(gen, *memory_, count);
        for (int i = 0; i < count; ++i)
        {
          float shape[3] = {1.f, 0.f, 1.f};
          if (i % 2 == 1)
            amcr::obliqueShape(static_cast<float>(1.0 + 3.0 * unit(gen)), static_cast<float>(M_PI * unit(gen)),
                               shape);
          for (int e = 0; e < 3; ++e)
            initial.shape[e][i] = shape[e];
        }
        const cv::Point at0 = amcr::nearestTablePixel(initial.x[0], initial.y[0]);
        const amcr::VRayEnds v = randomVEnds(gen, (*memory_)[initial.prototype[0]], at0,
                                             amcr::angleToBin(initial.theta[0]), p.max_affine_scale);
        amcr::MParticleSet fast = initial, ref = initial;
        model.measure(*memory_, v, fast, 0, count);
        model.measureReference(*memory_, v, ref, 0, count);
        for (int i = 0; i < count; ++i)
        {
          expectSameParticle(fast, ref, i, describe(p) + ", refits " + std::to_string(refits), bitwise_equal);
          if (HasFatalFailure())
            return;
          (fast.affine_valid[i] ? accepted : refused)++;
        }
        compared += count;
      }
      EXPECT_GE(accepted, 1) << describe(p);
      EXPECT_GE(refused, 10) << describe(p);
      if (kBitwise)
      {
        EXPECT_EQ(bitwise_equal, compared) << describe(p);
      }
    }
}

// An M-particle outside its table: InputError naming it, from both paths,
// with the M-particles before it updated alike.
TEST_F(UpdateLoop, OutsideTheTableThrowsAndNamesTheParticleInBothPaths)
{
  std::mt19937_64 gen(16);
  for (amcr::RayCorrespondence correspondence : {amcr::RayCorrespondence::kPaper, amcr::RayCorrespondence::kAffine})
  {
    for (int outside : {0, 5, 31, 32, 37, 70})
    {
      amcr::Params params;
      params.ray_correspondence = correspondence;
      const amcr::ObservationModel model(params);
      amcr::MParticleSet initial = randomMParticles(gen, *memory_, 80);
      for (int i = 0; i < 80; ++i)
        initial.shape[0][i] = initial.shape[2][i] = 1.f;  // frontal view shapes
      const cv::Point at0 = amcr::nearestTablePixel(initial.x[0], initial.y[0]);
      const amcr::VRayEnds v =
          randomVEnds(gen, (*memory_)[initial.prototype[0]], at0, amcr::angleToBin(initial.theta[0]), 3.0);
      const amcr::Prototype& p = (*memory_)[initial.prototype[outside]];
      if (outside % 2 == 0)
        initial.x[outside] = static_cast<float>(p.width()) - 0.5f;  // rounds to width
      else
        initial.y[outside] = -0.51f;  // rounds to -1
      amcr::MParticleSet fast = initial, ref = initial;
      std::string fast_what, ref_what;
      try
      {
        model.measure(*memory_, v, fast, 0, 80);
      }
      catch (const amcr::InputError& e)
      {
        fast_what = e.what();
      }
      try
      {
        model.measureReference(*memory_, v, ref, 0, 80);
      }
      catch (const amcr::InputError& e)
      {
        ref_what = e.what();
      }
      EXPECT_NE(fast_what.find("M-particle " + std::to_string(outside) + " "), std::string::npos) << fast_what;
      EXPECT_NE(fast_what.find(p.label()), std::string::npos) << fast_what;
      EXPECT_EQ(fast_what, ref_what);
      int bitwise_equal = 0;
      for (int i = 0; i < 80; ++i)
      {
        expectSameParticle(fast, ref, i, "outside at " + std::to_string(outside), bitwise_equal);
        if (HasFatalFailure())
          return;
      }
    }
  }
}

// The heading proposal: the same bin as the reference, frontal offsets and
// those of oblique view shapes, over signatures made from the tables
// (scaled, with noise and dropped rays) and at random.
TEST_F(UpdateLoop, BestHeadingBinEqualsTheReference)
{
  std::mt19937_64 gen(1216);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0, proposed = 0;
  for (std::size_t prototype = 0; prototype < memory_->size(); ++prototype)
  {
    const amcr::Prototype& p = (*memory_)[prototype];
    for (int trial = 0; trial < 600; ++trial)
    {
      const bool interior = trial % 2 == 0;
      const cv::Point at = interior ? p.interior()[gen() % p.interior().size()]
                                    : cv::Point(static_cast<int>(gen() % p.width()),
                                                static_cast<int>(gen() % p.height()));
      const cv::Point from = gen() % 4 == 0 ? cv::Point(static_cast<int>(gen() % p.width()),
                                                        static_cast<int>(gen() % p.height()))
                                            : at;
      amcr::RaySignature s = amcr_test::tableRays(p, from.x, from.y, static_cast<int>(gen() % amcr::kDirectionBins),
                                                  static_cast<float>(0.3 + 3 * unit(gen)));
      std::normal_distribution<double> noise(0.0, 2.0 * unit(gen));
      for (int k = 0; k < kFeatureRays; ++k)
      {
        if (gen() % 8 == 0)
          s.distance[k] = 0.f;
        else if (gen() % 8 == 0)
          s.distance[k] = static_cast<float>(200 * unit(gen));
        else if (s.distance[k] > 0.f)
          s.distance[k] = static_cast<float>(std::max(0.01, s.distance[k] + noise(gen)));
      }
      const int frontal = amcr::bestHeadingBin(p, at.x, at.y, s);
      ASSERT_EQ(frontal, amcr::bestHeadingBinReference(p, at.x, at.y, s)) << p.label() << " at " << at;
      const float stretch = static_cast<float>(std::exp(0.8 * (2 * unit(gen) - 1)));
      const float turn = static_cast<float>(2 * M_PI * unit(gen));
      const float c = std::cos(turn), sn = std::sin(turn);
      // R diag(stretch, 1 / stretch) R^T: det 1, symmetric.
      const float shape[3] = {c * c * stretch + sn * sn / stretch, c * sn * (stretch - 1 / stretch),
                              sn * sn * stretch + c * c / stretch};
      const amcr::RayOffsets offsets(shape, static_cast<float>(2 * M_PI * unit(gen) - M_PI));
      ASSERT_EQ(amcr::bestHeadingBin(p, at.x, at.y, s, offsets),
                amcr::bestHeadingBinReference(p, at.x, at.y, s, offsets))
          << p.label() << " at " << at << ", oblique";
      compared += 2;
      proposed += frontal >= 0 ? 1 : 0;
    }
  }
  EXPECT_GT(proposed, compared / 4);  // most signatures had a heading to find
}
}  // namespace
