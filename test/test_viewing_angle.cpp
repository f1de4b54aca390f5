// Anisotropy and viewing angle of a prototype -> image affine
// (include/amcr/extraction/viewing_angle.h).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/extraction/viewing_angle.h"
#include "scene_drawing.h"

namespace
{
TEST(ViewingAngle, ASquashOfTwoIsSixtyDegreesWhateverTheRotationAndScale)
{
  for (double rotation : {0.0, 0.7, -2.0})
    for (double scale : {0.5, 1.0, 3.0})
    {
      const amcr::Affine a = amcr_test::makeAffine({100, 100}, {320, 240}, rotation, scale, scale / 2.0, 0.0);
      const double anisotropy = amcr::affineAnisotropy(a);
      EXPECT_NEAR(anisotropy, 2.0, 1e-9) << "rotation " << rotation << " scale " << scale;
      EXPECT_NEAR(amcr::viewingAngleDegrees(anisotropy), 60.0, 1e-7);
    }
}

TEST(ViewingAngle, FrontalThreeToOneAndShear)
{
  EXPECT_NEAR(amcr::affineAnisotropy(amcr::identityAffine()), 1.0, 1e-12);
  EXPECT_NEAR(amcr::viewingAngleDegrees(1.0), 0.0, 1e-12);
  // The squash may run along any direction: turned after and before.
  const amcr::Affine squash = amcr_test::makeAffine({0, 0}, {0, 0}, 0.4, 1.0, 3.0, 0.0);
  const amcr::Affine turned = amcr::composeAffine(amcr::Affine(std::cos(1.1), -std::sin(1.1), 0, std::sin(1.1),
                                                               std::cos(1.1), 0),
                                                  squash);
  EXPECT_NEAR(amcr::affineAnisotropy(turned), 3.0, 1e-9);
  EXPECT_NEAR(amcr::viewingAngleDegrees(3.0), std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(amcr::viewingAngleDegrees(3.0), 70.53, 0.01);
  // A shear of 1 ([1 1; 0 1]): singular values (sqrt(5) +- 1) / 2, ratio 2.618.
  EXPECT_NEAR(amcr::affineAnisotropy(amcr::Affine(1, 1, 0, 0, 1, 0)), (std::sqrt(5.0) + 1) / (std::sqrt(5.0) - 1), 1e-9);
  // A mirror does not change the squash.
  EXPECT_NEAR(amcr::affineAnisotropy(amcr::Affine(-2, 0, 0, 0, 1, 0)), 2.0, 1e-12);
}

TEST(ViewingAngle, SingularAndBadInput)
{
  EXPECT_TRUE(std::isinf(amcr::affineAnisotropy(amcr::Affine(1, 2, 0, 2, 4, 0))));
  EXPECT_NEAR(amcr::viewingAngleDegrees(std::numeric_limits<double>::infinity()), 90.0, 1e-12);
  EXPECT_THROW(amcr::viewingAngleDegrees(0.5), amcr::InputError);
  EXPECT_THROW(amcr::viewingAngleDegrees(std::nan("")), amcr::InputError);
  EXPECT_THROW(amcr::affineAnisotropy(amcr::Affine(1, 0, std::nan(""), 0, 1, 0)), amcr::InputError);
}
}  // namespace
