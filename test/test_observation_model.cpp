// The observation model O (paper eqs. 5-6) against hand-computed values.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/observation_model.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "amcr/filter/relational_update.h"
#include "scene_drawing.h"

namespace
{
amcr::Params paperParams()
{
  amcr::Params p;
  p.likelihood_form = amcr::LikelihoodForm::kPaper;
  p.p_outlier = 0.1;
  p.sigma_w = 10.0;
  p.p_invalid = 0.1;
  p.max_ray_length = 200.0;
  return p;
}

// Paper eq. 5 with p_outlier = 0.1, sigma_w = 10 px:
//   log p(dw) = log(0.1 + 0.9 * exp(-dw^2 / 200) / (10 * sqrt(2 pi)))
// 1 / (10 sqrt(2 pi)) = 0.0398942280.
//   dw =  0: log(0.1 + 0.9 * 0.0398942280)                 = log(0.1359048)  = -1.99580060
//   dw =  5: log(0.1 + 0.9 * 0.0398942280 * exp(-0.125))    = log(0.1316859)  = -2.02733589
//   dw = 10: log(0.1 + 0.9 * 0.0398942280 * exp(-0.5))      = log(0.1217775)  = -2.10556078
//   dw = 20: log(0.1 + 0.9 * 0.0398942280 * exp(-2))        = log(0.1048591)  = -2.25513691
//   dw = 50: log(0.1 + 0.9 * 0.0398942280 * exp(-12.5))     = log(0.1000001)  = -2.30258375
// (values from Python's math module, 12 digits).
TEST(ObservationModel, PaperFormEqualsHandComputedEq5)
{
  const amcr::ObservationModel model(paperParams());
  EXPECT_NEAR(model.logRay(0.0), -1.99580059983, 1e-9);
  EXPECT_NEAR(model.logRay(5.0), -2.02733589383, 1e-9);
  EXPECT_NEAR(model.logRay(10.0), -2.10556077672, 1e-9);
  EXPECT_NEAR(model.logRay(20.0), -2.25513690519, 1e-9);
  EXPECT_NEAR(model.logRay(50.0), -2.30258375495, 1e-9);
  // The deviation is a distance: the sign does not matter.
  EXPECT_NEAR(model.logRay(-10.0), model.logRay(10.0), 1e-12);
  // Far away only the outlier floor is left: log(0.1).
  EXPECT_NEAR(model.logRay(1000.0), std::log(0.1), 1e-9);
}

// The normalised mixture: log(p_outlier / L + (1 - p_outlier) N(dw; 0, sigma_w^2)),
// L = max_ray_length = 200 px, so p_outlier / L = 0.0005:
//   dw =  0: log(0.0005 + 0.9 * 0.0398942280)               = -3.31305450107
//   dw =  5: log(0.0005 + 0.9 * 0.0398942280 * exp(-0.125))  = -3.43622745029
//   dw = 10: log(0.0005 + 0.9 * 0.0398942280 * exp(-0.5))    = -3.80418412914
//   dw = 20: log(0.0005 + 0.9 * 0.0398942280 * exp(-2))      = -5.22894299709
//   dw = 50: log(0.0005 + 0.9 * 0.0398942280 * exp(-12.5))   = -7.60063488583
TEST(ObservationModel, MixtureFormEqualsHandComputedValues)
{
  amcr::Params p = paperParams();
  p.likelihood_form = amcr::LikelihoodForm::kMixture;
  const amcr::ObservationModel model(p);
  EXPECT_NEAR(model.logRay(0.0), -3.31305450107, 1e-9);
  EXPECT_NEAR(model.logRay(5.0), -3.43622745029, 1e-9);
  EXPECT_NEAR(model.logRay(10.0), -3.80418412914, 1e-9);
  EXPECT_NEAR(model.logRay(20.0), -5.22894299709, 1e-9);
  EXPECT_NEAR(model.logRay(50.0), -7.60063488583, 1e-9);
  EXPECT_NEAR(model.logRay(1e4), std::log(0.1 / 200.0), 1e-9);
}

// The same formulas for other settings, written as code (not hand values).
TEST(ObservationModel, BothFormsFollowTheirFormulaForOtherSettings)
{
  for (double sigma : {3.0, 5.0, 10.0, 25.0})
    for (double p_out : {0.0, 0.05, 0.3, 1.0})
      for (double length : {50.0, 200.0, 800.0})
        for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
        {
          amcr::Params p = paperParams();
          p.sigma_w = sigma;
          p.p_outlier = p_out;
          p.max_ray_length = length;
          p.likelihood_form = form;
          const amcr::ObservationModel model(p);
          const double floor = form == amcr::LikelihoodForm::kPaper ? p_out : p_out / length;
          for (double dw : {0.0, 1.0, 2.5, 7.0, 15.0, 40.0})
          {
            const double gauss = std::exp(-dw * dw / (2 * sigma * sigma)) / (sigma * std::sqrt(2 * M_PI));
            const double expected = std::log(floor + (1 - p_out) * gauss);
            if (!std::isfinite(expected))
              continue;  // p_outlier = 1 and far: log 0 is not compared
            EXPECT_NEAR(model.logRay(dw), expected, 1e-9)
                << "sigma " << sigma << " p_outlier " << p_out << " L " << length << " form "
                << amcr::toString(form) << " dw " << dw;
          }
        }
}

TEST(ObservationModel, LogInvalidIsLogPInvalid)
{
  for (double pi : {0.1, 0.02, 0.5})
  {
    amcr::Params p = paperParams();
    p.p_invalid = pi;
    EXPECT_NEAR(amcr::ObservationModel(p).logInvalid(), std::log(pi), 1e-12);
  }
}

// The mixture form's terms are densities over the ray's range [0, L]: an
// invalid ray weighs p_invalid / L, as an outlier weighs p_outlier / L.
// With p_invalid itself (a probability, 0.1 against at most 0.07 for a
// perfect ray at sigma_w 5), an M-particle where no ray meets an edge
// outscored one where all eight fit, and the form recognized nothing.
TEST(ObservationModel, MixtureFormWeighsAnInvalidRayAsADensity)
{
  amcr::Params p = paperParams();
  p.likelihood_form = amcr::LikelihoodForm::kMixture;
  p.sigma_w = 5.0;
  const amcr::ObservationModel model(p);
  EXPECT_NEAR(model.logInvalid(), std::log(0.1 / 200.0), 1e-12);
  EXPECT_GT(model.logRay(0.0), model.logInvalid() + 4.0) << "a fitting ray must outweigh a missing one";
  EXPECT_GT(model.logRay(2.0 * p.sigma_w), model.logInvalid()) << "so must a ray 2 sigma_w off";
}

/// A relational particle whose deviations are known: an M-particle at a
/// pixel of a drawn star where all 8 feature rays meet an edge, the identity
/// affine (B = A = I), and V-particle rays ending dw[k] px to the right of
/// the table's ray k. Both deviation spaces then see dw[k] on ray k.
class KnownDeviations
{
public:
  KnownDeviations() : prototype_("star", amcr_test::drawPrototype(amcr_test::ShapeId::kStar), 128, 40.0, 1.0)
  {
    const std::vector<cv::Point>& interior = prototype_.interior();
    at_ = interior[interior.size() / 2];
    raw_ = prototype_.rawDistances(at_.x, at_.y);
    const float identity[6] = {1, 0, 0, 0, 1, 0};
    std::copy(identity, identity + 6, affine_.table_to_image);
    std::copy(identity, identity + 6, affine_.image_to_table);
  }

  /// Whether every feature ray of the M-particle meets an edge (the premise).
  bool allTableRaysValid() const
  {
    for (int k = 0; k < amcr::kFeatureRays; ++k)
      if (raw_[k * amcr::kFeatureBinStep] == amcr::Prototype::kNoEdge)
        return false;
    return true;
  }

  /// The model's eq. 6 for V rays valid[k] with deviations dw[k] (px).
  float logLikelihood(const amcr::ObservationModel& model, const float* dw, const bool* valid) const
  {
    amcr::VRayEnds v;
    for (int k = 0; k < amcr::kFeatureRays; ++k)
    {
      float x = 0.f, y = 0.f;
      amcr::tableRayEnd(raw_, at_, k * amcr::kFeatureBinStep, x, y);
      v.feature_x[k] = x + dw[k];
      v.feature_y[k] = y;
      v.feature_valid[k] = valid[k];
      v.invalid_feature_rays += valid[k] ? 0 : 1;
    }
    return model.logLikelihood(v, raw_, at_, 0, affine_);
  }

private:
  amcr::Prototype prototype_;
  cv::Point at_;
  const std::uint8_t* raw_ = nullptr;
  amcr::RelationalAffine affine_;
};

// Paper eq. 6: log p(z | x) = sum over valid rays of log p(dw_j) + n_invalid * log p_invalid.
// 8 rays, 3 invalid; valid dw = 0, 5, 10, 20, 50 (paper form):
//   -1.99580060 - 2.02733589 - 2.10556078 - 2.25513691 - 2.30258375 + 3 * log(0.1)
//   = -10.68641793 - 6.90775528 = -17.59417321
TEST(ObservationModel, LogLikelihoodIsEq6)
{
  const KnownDeviations known;
  ASSERT_TRUE(known.allTableRaysValid());
  for (amcr::DeviationSpace space : {amcr::DeviationSpace::kImage, amcr::DeviationSpace::kPrototype})
  {
    amcr::Params params = paperParams();
    params.deviation_space = space;
    const amcr::ObservationModel model(params);
    const float dw[8] = {0.f, 123.f, 5.f, 10.f, 77.f, 20.f, 50.f, 0.f};
    const bool valid[8] = {true, false, true, true, false, true, true, false};
    // The dw of invalid rays is junk and must be ignored. Tolerance 8 * 1e-3:
    // the model uses its tabulated per-ray term (logRayFromSquared).
    EXPECT_NEAR(known.logLikelihood(model, dw, valid), -17.59417321, 8e-3) << amcr::toString(space);

    // All invalid: 8 * log(0.1), summed in float (1e-5 is a few float ulps here).
    const bool none[8] = {false, false, false, false, false, false, false, false};
    EXPECT_NEAR(known.logLikelihood(model, dw, none), 8 * std::log(0.1), 1e-5) << amcr::toString(space);
  }

  // Against the model's own logRay for random rays, paper and mixture forms.
  for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
  {
    amcr::Params p = paperParams();
    p.likelihood_form = form;
    p.p_invalid = 0.07;
    const amcr::ObservationModel m(p);
    unsigned state = 12345;
    for (int trial = 0; trial < 200; ++trial)
    {
      float d[8];
      bool v[8];
      double expected = 0.0;
      for (int j = 0; j < 8; ++j)
      {
        state = state * 1664525u + 1013904223u;
        d[j] = (state >> 8) % 6000 / 100.f;  // 0 .. 60 px
        v[j] = (state >> 3) % 4 != 0;
        expected += v[j] ? m.logRay(d[j]) : m.logInvalid();
      }
      EXPECT_NEAR(known.logLikelihood(m, d, v), expected, 8e-3) << amcr::toString(form) << " trial " << trial;
    }
  }
}

TEST(ObservationModel, TabulatedTermMatchesLogRay)
{
  for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
    for (double sigma : {3.0, 5.0, 10.0})
    {
      amcr::Params p = paperParams();
      p.likelihood_form = form;
      p.sigma_w = sigma;
      const amcr::ObservationModel model(p);
      double worst = 0.0, worst_dw = 0.0;
      for (double dw = 0.0; dw <= 400.0; dw += 0.01)
      {
        const double diff = std::abs(model.logRayFromSquared(static_cast<float>(dw * dw)) - model.logRay(dw));
        if (diff > worst)
        {
          worst = diff;
          worst_dw = dw;
        }
      }
      EXPECT_LT(worst, 1e-3) << amcr::toString(form) << " sigma_w " << sigma << ": worst at dw = " << worst_dw;
    }
}

TEST(ObservationModel, CloserIsNeverLessLikely)
{
  for (amcr::LikelihoodForm form : {amcr::LikelihoodForm::kPaper, amcr::LikelihoodForm::kMixture})
  {
    amcr::Params p = paperParams();
    p.likelihood_form = form;
    const amcr::ObservationModel model(p);
    for (double dw = 0.0; dw < 100.0; dw += 0.5)
      EXPECT_GE(model.logRay(dw), model.logRay(dw + 0.5)) << amcr::toString(form) << " dw " << dw;
  }
}
}  // namespace
