// The relational update (ObservationModel::measure, paper 3.6 / 4.1 / eqs.
// 5-6), float and tabulated, against a plain double-precision reference
// written here: the affine from the three triangle correspondences solved as
// a linear system, its inverse, its singular values, eq. 5 per ray and eq. 6
// as the sum of the logs. In the style of laser_filters' detector tests: a
// seeded sweep of random particles over both deviation spaces, both
// likelihood forms and several thresholds.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "amcr/base/errors.h"
#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/filter/relational_update.h"
#include "scene_drawing.h"

namespace
{
using amcr::kFeatureRays;
using amcr::kTriangleRays;

// Tolerances for float arithmetic and the table of eq. 5, each about 4 times
// the worst case measured over the sweep below (in brackets):
constexpr double kEndTolerance = 2.5e-4;         // px, a V ray end point [6.1e-5]
constexpr double kDeviationTolerance = 5e-3;     // px, dw_j of one ray, relative beyond 100 px [1.1e-3]
constexpr double kRayTermTolerance = 1.5e-3;     // log p(dw_j) of eq. 5, the table included [3.3e-4]
constexpr double kLogLikelihoodTolerance = 2e-3; // eq. 6 over the 8 rays [4.7e-4]
constexpr double kAffineTolerance = 1.5e-4;      // A applied to a V ray end, relative to the result (px) [3.3e-5]
// Where the model and the reference may decide differently (accept/refuse):
// within this relative distance of a threshold (triangle area, largest or
// smallest singular value). None did in the sweep; float rounding is ~1e-6.
constexpr double kBoundaryEpsilon = 1e-4;

/// A V-particle's raw measurement: 8 feature rays, then the rays at 120 and 240 deg.
struct VMeasurement
{
  amcr::VParticle v;
  float distance[kFeatureRays + 2];
  bool valid[kFeatureRays + 2];
};

/// What the reference finds for one relational particle.
struct Reference
{
  bool accepted = false;
  /// Relative distance of the deciding quantity to its threshold (areas,
  /// singular values); infinite when no threshold was involved.
  double margin = std::numeric_limits<double>::infinity();
  cv::Matx33d table_to_image;  // B, homogeneous
  cv::Matx33d image_to_table;  // A = B^-1
  double log_likelihood = 0.0;
  double deviation[kFeatureRays] = {};  // dw_j of the rays valid on both sides, else -1
  double ray_term[kFeatureRays] = {};   // the term of ray j in eq. 6
};

/// Paper eq. 5, written out: log(floor + (1 - p_outlier) N(dw; 0, sigma_w^2)).
double referenceLogRay(const amcr::Params& p, double dw)
{
  const double floor = p.likelihood_form == amcr::LikelihoodForm::kPaper ? p.p_outlier : p.p_outlier / p.max_ray_length;
  const double gauss = std::exp(-dw * dw / (2 * p.sigma_w * p.sigma_w)) / (p.sigma_w * std::sqrt(2 * M_PI));
  return std::log(floor + (1 - p.p_outlier) * gauss);
}

cv::Point2d vRayEnd(const amcr::VParticle& v, double angle, double distance)
{
  return {v.x + distance * std::cos(v.theta + angle), v.y + distance * std::sin(v.theta + angle)};
}

/// Where table ray `bin` (any multiple of a turn added) from `at` ends; false when it meets no edge.
bool tableEnd(const amcr::Prototype& p, const cv::Point& at, int bin, cv::Point2d& end)
{
  const float d = p.distance(at.x, at.y, bin % amcr::kDirectionBins);
  if (d < 0.f)
    return false;
  const double a = amcr::binToAngle(bin % amcr::kDirectionBins);
  end = {at.x + d * std::cos(a), at.y + d * std::sin(a)};
  return true;
}

/// The affine taking src[i] to dst[i]: two 3x3 linear systems [x y 1] m = x'.
cv::Matx33d solveAffine(const cv::Point2d src[3], const cv::Point2d dst[3])
{
  const cv::Matx33d s(src[0].x, src[0].y, 1, src[1].x, src[1].y, 1, src[2].x, src[2].y, 1);
  const cv::Matx33d s_inverse = s.inv(cv::DECOMP_LU);
  const cv::Vec3d row_x = s_inverse * cv::Vec3d(dst[0].x, dst[1].x, dst[2].x);
  const cv::Vec3d row_y = s_inverse * cv::Vec3d(dst[0].y, dst[1].y, dst[2].y);
  return {row_x[0], row_x[1], row_x[2], row_y[0], row_y[1], row_y[2], 0, 0, 1};
}

double twiceArea(const cv::Point2d t[3])
{
  return std::abs((t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y));
}

/// The affine B and its checks: both triangles' areas, no mirror, scales in bounds.
bool referenceAffine(const amcr::Params& p, const cv::Point2d table[3], const cv::Point2d image[3], Reference& r)
{
  const double area_limit = 2 * p.min_triangle_area;
  const double areas[2] = {twiceArea(table), twiceArea(image)};
  for (double area : areas)
  {
    r.margin = std::min(r.margin, std::abs(area / area_limit - 1));
    if (area < area_limit)
      return false;
  }
  r.table_to_image = solveAffine(table, image);
  const cv::Matx22d linear(r.table_to_image(0, 0), r.table_to_image(0, 1), r.table_to_image(1, 0),
                           r.table_to_image(1, 1));
  cv::Matx21d singular;
  cv::SVD::compute(linear, singular, cv::SVD::NO_UV);
  const double max_scale = p.max_affine_scale;
  r.margin = std::min({r.margin, std::abs(singular(0) / max_scale - 1), std::abs(singular(1) * max_scale - 1)});
  if (cv::determinant(linear) <= 0 || singular(0) > max_scale || singular(1) < 1 / max_scale)
    return false;
  r.image_to_table = r.table_to_image.inv(cv::DECOMP_LU);
  return true;
}

/// The whole relational update of one M-particle, in double.
Reference reference(const amcr::Params& p, const amcr::Prototype& prototype, const VMeasurement& z, float mx,
                    float my, float mtheta)
{
  Reference r;
  // Eq. 6's term of an invalid ray; the mixture form's terms are densities over [0, L].
  const double log_invalid = std::log(p.likelihood_form == amcr::LikelihoodForm::kPaper ? p.p_invalid
                                                                                       : p.p_invalid / p.max_ray_length);
  r.log_likelihood = kFeatureRays * log_invalid;
  std::fill(r.deviation, r.deviation + kFeatureRays, -1.0);
  // The table pixel and direction bin the model looks up are part of its
  // definition (the tables are discrete), not an approximation to check.
  const cv::Point at = amcr::nearestTablePixel(mx, my);
  const int bin = amcr::angleToBin(mtheta);
  cv::Point2d table[3], image[3];
  for (int t = 0; t < kTriangleRays; ++t)
  {
    const int ray = t == 0 ? 0 : kFeatureRays + t - 1;
    if (!z.valid[ray] || !tableEnd(prototype, at, bin + t * amcr::kTriangleBinStep, table[t]))
      return r;
    image[t] = vRayEnd(z.v, t * 2 * M_PI / 3, z.distance[ray]);
  }
  r.accepted = referenceAffine(p, table, image, r);
  if (!r.accepted)
    return r;
  r.log_likelihood = 0.0;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    cv::Point2d q;
    if (!z.valid[k] || !tableEnd(prototype, at, bin + k * amcr::kFeatureBinStep, q))
    {
      r.ray_term[k] = log_invalid;
      r.log_likelihood += log_invalid;
      continue;
    }
    const cv::Point2d v_end = vRayEnd(z.v, k * M_PI / 4, z.distance[k]);
    const cv::Matx33d& m = p.deviation_space == amcr::DeviationSpace::kImage ? r.table_to_image : r.image_to_table;
    const cv::Point2d from = p.deviation_space == amcr::DeviationSpace::kImage ? q : v_end;
    const cv::Point2d to = p.deviation_space == amcr::DeviationSpace::kImage ? v_end : q;
    const cv::Vec3d mapped = m * cv::Vec3d(from.x, from.y, 1);
    r.deviation[k] = std::hypot(mapped[0] - to.x, mapped[1] - to.y);
    r.ray_term[k] = referenceLogRay(p, r.deviation[k]);
    r.log_likelihood += r.ray_term[k];
  }
  return r;
}

/// A random V-particle measurement: in 70 % of the cases the scans of table
/// pixel `at` and bin `bin`, scaled and with noise (as a V-particle on the
/// object sees them, so that many affines pass), else random distances.
VMeasurement randomMeasurement(std::mt19937_64& gen, const amcr::Prototype& prototype, const cv::Point& at, int bin,
                               double max_scale)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  VMeasurement z;
  z.v.x = static_cast<float>(640 * unit(gen));
  z.v.y = static_cast<float>(480 * unit(gen));
  z.v.theta = static_cast<float>(2 * M_PI * unit(gen) - M_PI);
  const bool on_object = unit(gen) < 0.7;
  // Scales up to 1.3 times past the accepted range either way.
  const double scale = std::exp((2 * unit(gen) - 1) * 1.3 * std::log(max_scale));
  std::normal_distribution<double> noise(0.0, 4.0 * unit(gen));
  for (int j = 0; j < kFeatureRays + 2; ++j)
  {
    const int ray_bin = j < kFeatureRays ? bin + j * amcr::kFeatureBinStep
                                         : bin + (j - kFeatureRays + 1) * amcr::kTriangleBinStep;
    const float table_distance = prototype.distance(at.x, at.y, ray_bin % amcr::kDirectionBins);
    double d = 2 + 150 * unit(gen);
    if (on_object && table_distance > 0.f)
      d = std::max(0.5, scale * table_distance + noise(gen));
    z.distance[j] = static_cast<float>(d);
    z.valid[j] = unit(gen) > 0.1;
  }
  return z;
}

std::string describe(const amcr::Params& p)
{
  std::ostringstream s;
  s << amcr::toString(p.deviation_space) << " space, " << amcr::toString(p.likelihood_form) << " form, sigma_w "
    << p.sigma_w << ", min_triangle_area " << p.min_triangle_area << ", max_affine_scale " << p.max_affine_scale;
  return s.str();
}

/// The sweep: every parameter setting below, for every shape of the drawn memory.
std::vector<amcr::Params> sweptParams()
{
  std::vector<amcr::Params> out;
  for (amcr::DeviationSpace space : {amcr::DeviationSpace::kImage, amcr::DeviationSpace::kPrototype})
    for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
      for (double sigma : {3.0, 5.0, 10.0})
        for (const std::pair<double, double>& limits : {std::make_pair(20.0, 8.0), std::make_pair(5.0, 3.0),
                                                         std::make_pair(150.0, 1.5)})
        {
          amcr::Params p;
          p.ray_correspondence = amcr::RayCorrespondence::kPaper;  // the affine-corrected path: test_corrected_scan.cpp
          p.deviation_space = space;
          p.likelihood_form = form;
          p.sigma_w = sigma;
          p.p_invalid = 0.07;
          p.min_triangle_area = limits.first;
          p.max_affine_scale = limits.second;
          out.push_back(p);
        }
  return out;
}

/// Counts of a sweep, for the assertions that it covered every case.
struct SweepCounts
{
  int particles = 0, accepted = 0, refused = 0, near_boundary_disagreements = 0;
};

class RelationalUpdate : public ::testing::Test
{
protected:
  static void SetUpTestSuite() { memory_ = amcr_test::drawnMemory(amcr_test::allShapes()); }
  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
};
std::shared_ptr<const amcr::PrototypeMemory> RelationalUpdate::memory_;

/// `count` M-particles: the odd ones anywhere in their tables, the even ones
/// within 2 px and 0.15 rad of the first (a cloud around a pose).
amcr::MParticleSet randomMParticles(std::mt19937_64& gen, const amcr::PrototypeMemory& memory, int count)
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  amcr::MParticleSet m;
  m.resize(count);
  for (int i = 0; i < count; ++i)
  {
    const bool near_first = i > 0 && i % 2 == 0;
    m.prototype[i] = near_first ? m.prototype[0] : static_cast<int>(gen() % memory.size());
    const amcr::Prototype& prototype = memory[m.prototype[i]];
    m.x[i] = static_cast<float>(unit(gen) * (prototype.width() - 1));
    m.y[i] = static_cast<float>(unit(gen) * (prototype.height() - 1));
    m.theta[i] = static_cast<float>(2 * M_PI * unit(gen) - M_PI);
    if (near_first)
    {
      m.x[i] = std::min(std::max(m.x[0] + static_cast<float>(4 * unit(gen) - 2), 0.f), prototype.width() - 1.f);
      m.y[i] = std::min(std::max(m.y[0] + static_cast<float>(4 * unit(gen) - 2), 0.f), prototype.height() - 1.f);
      m.theta[i] = m.theta[0] + static_cast<float>(0.3 * unit(gen) - 0.15);
    }
  }
  return m;
}

/// For an M-particle both accept: A against the reference's, then eq. 5 ray
/// by ray through the model's named pieces.
void compareAcceptedParticle(const amcr::Params& p, const amcr::ObservationModel& model,
                             const amcr::Prototype& prototype, const amcr::MParticleSet& m, int i,
                             const amcr::VRayEnds& ends, const Reference& r)
{
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const cv::Point2d e(ends.feature_x[k], ends.feature_y[k]);
    const cv::Vec3d want = r.image_to_table * cv::Vec3d(e.x, e.y, 1);
    const double gx = m.affine[0][i] * e.x + m.affine[1][i] * e.y + m.affine[2][i];
    const double gy = m.affine[3][i] * e.x + m.affine[4][i] * e.y + m.affine[5][i];
    ASSERT_LT(std::hypot(gx - want[0], gy - want[1]), kAffineTolerance * std::max(1.0, cv::norm(want)))
        << describe(p) << ", particle " << i << ", ray " << k;
  }
  const cv::Point at = amcr::nearestTablePixel(m.x[i], m.y[i]);
  const int bin = amcr::angleToBin(m.theta[i]);
  const std::uint8_t* raw = prototype.rawDistances(at.x, at.y);
  float tx[kTriangleRays], ty[kTriangleRays];
  amcr::RelationalAffine affine;
  ASSERT_TRUE(amcr::tableTriangle(raw, at, bin, tx, ty));
  ASSERT_TRUE(amcr::fitRelationalAffine(tx, ty, ends, static_cast<float>(p.min_triangle_area),
                                        static_cast<float>(p.max_affine_scale), affine));
  for (int k = 0; k < kFeatureRays; ++k)
  {
    float qx, qy;
    if (r.deviation[k] < 0 ||
        !amcr::tableRayEnd(raw, at, (bin + k * amcr::kFeatureBinStep) % amcr::kDirectionBins, qx, qy))
      continue;
    const float dw2 = amcr::squaredDeviation(affine, p.deviation_space, qx, qy, ends.feature_x[k], ends.feature_y[k]);
    ASSERT_NEAR(std::sqrt(dw2), r.deviation[k], kDeviationTolerance * std::max(1.0, r.deviation[k] / 100))
        << describe(p) << ", particle " << i << ", ray " << k;
    ASSERT_NEAR(model.logRayFromSquared(dw2), r.ray_term[k], kRayTermTolerance)
        << describe(p) << ", particle " << i << ", ray " << k << ", dw " << r.deviation[k];
  }
}

/// Compares one V-particle's update of `count` M-particles with the reference.
void compareOneV(const amcr::Params& p, const amcr::PrototypeMemory& memory, std::mt19937_64& gen, int count,
                 SweepCounts& counts)
{
  const amcr::ObservationModel model(p);
  amcr::MParticleSet m = randomMParticles(gen, memory, count);
  const cv::Point first_at = amcr::nearestTablePixel(m.x[0], m.y[0]);
  const VMeasurement z =
      randomMeasurement(gen, memory[m.prototype[0]], first_at, amcr::angleToBin(m.theta[0]), p.max_affine_scale);
  const amcr::VRayEnds ends = amcr::rayEnds(z.v, z.distance, z.valid);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const cv::Point2d e = vRayEnd(z.v, k * M_PI / 4, z.distance[k]);
    ASSERT_NEAR(ends.feature_x[k], e.x, kEndTolerance);
    ASSERT_NEAR(ends.feature_y[k], e.y, kEndTolerance);
  }
  model.measure(memory, ends, m, 0, count);

  for (int i = 0; i < count; ++i)
  {
    const amcr::Prototype& prototype = memory[m.prototype[i]];
    const Reference r = reference(p, prototype, z, m.x[i], m.y[i], m.theta[i]);
    ++counts.particles;
    const bool fast_accepted = m.affine_valid[i] != 0;
    if (fast_accepted != r.accepted)
    {
      ASSERT_LT(r.margin, kBoundaryEpsilon) << describe(p) << ": particle " << i << " accepted " << fast_accepted
                                            << " by the model, " << r.accepted << " by the reference";
      ++counts.near_boundary_disagreements;
      continue;
    }
    (r.accepted ? counts.accepted : counts.refused)++;
    ASSERT_NEAR(m.log_likelihood[i], r.log_likelihood, kLogLikelihoodTolerance) << describe(p) << ", particle " << i;
    if (r.accepted)
      compareAcceptedParticle(p, model, prototype, m, i, ends, r);
    if (::testing::Test::HasFatalFailure())
      return;
  }
}

TEST_F(RelationalUpdate, FastPathEqualsTheDoubleReferenceOverASweep)
{
  std::mt19937_64 gen(20261203);
  for (const amcr::Params& p : sweptParams())
  {
    SweepCounts counts;
    for (int v = 0; v < 200; ++v)
    {
      compareOneV(p, *memory_, gen, 24, counts);
      if (HasFatalFailure())
        return;
    }
    // The sweep must have exercised both outcomes, and the boundary must be rare.
    EXPECT_GT(counts.accepted, counts.particles / 100) << describe(p);
    EXPECT_GT(counts.refused, counts.particles / 10) << describe(p);
    EXPECT_LE(counts.near_boundary_disagreements, counts.particles / 1000) << describe(p);
  }
}

// An M-particle outside its table is the caller's to re-seed: measure says so.
TEST_F(RelationalUpdate, RefusesAnMParticleOutsideItsTable)
{
  const amcr::ObservationModel model((amcr::Params()));
  amcr::MParticleSet m;
  m.resize(2);
  m.prototype = {0, 0};
  m.x = {5.f, -1.f};
  m.y = {5.f, 5.f};
  VMeasurement z{};
  std::fill(z.distance, z.distance + kFeatureRays + 2, 10.f);
  std::fill(z.valid, z.valid + kFeatureRays + 2, true);
  const amcr::VRayEnds ends = amcr::rayEnds(z.v, z.distance, z.valid);
  EXPECT_NO_THROW(model.measure(*memory_, ends, m, 0, 1));
  EXPECT_THROW(model.measure(*memory_, ends, m, 0, 2), amcr::InputError);
  m.x[1] = static_cast<float>((*memory_)[0].width()) - 0.4f;  // rounds to width: outside
  EXPECT_THROW(model.measure(*memory_, ends, m, 1, 2), amcr::InputError);
  m.x[1] = -0.4f;  // rounds to 0: inside
  EXPECT_NO_THROW(model.measure(*memory_, ends, m, 1, 2));
}

// Without a V triangle (a triangle ray met no edge) nothing is fitted: the
// likelihood is that of 8 invalid rays (eq. 6), whatever the M-particles.
TEST_F(RelationalUpdate, NoVTriangleMeansEightInvalidRays)
{
  amcr::Params p;
  p.p_invalid = 0.07;
  const amcr::ObservationModel model(p);
  std::mt19937_64 gen(5);
  for (int missing : {0, kFeatureRays, kFeatureRays + 1})
  {
    amcr::MParticleSet m;
    m.resize(1);
    m.prototype[0] = 1;
    m.x[0] = m.y[0] = 60.f;
    const cv::Point at(60, 60);
    VMeasurement z = randomMeasurement(gen, (*memory_)[1], at, 0, p.max_affine_scale);
    std::fill(z.valid, z.valid + kFeatureRays + 2, true);
    z.valid[missing] = false;
    model.measure(*memory_, amcr::rayEnds(z.v, z.distance, z.valid), m, 0, 1);
    EXPECT_EQ(m.affine_valid[0], 0) << "missing ray " << missing;
    EXPECT_NEAR(m.log_likelihood[0], 8 * std::log(0.07), 1e-5) << "missing ray " << missing;
  }
}
}  // namespace
