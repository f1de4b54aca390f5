#include "amcr/filter/motion_model.h"

#include <cmath>

#include "amcr/filter/corrected_scan.h"

namespace amcr
{
MotionModel::MotionModel(const MotionParams& motion, const ObservationParams& observation)
  : MotionModel(motion.motion_noise_translation, motion.motion_noise_rotation,
                observation.ray_correspondence == RayCorrespondence::kAffine ? motion.motion_noise_shape : 0.0)
{
}

MotionModel::MotionModel(double noise_translation, double noise_rotation, double noise_shape)
  : noise_translation_(noise_translation), noise_rotation_(noise_rotation), noise_shape_(noise_shape)
{
}

void MotionModel::moveV(VParticle& v, const Control& u)
{
  v.theta = static_cast<float>(v.theta + u.rotation);
  v.x = static_cast<float>(v.x + u.translation * std::cos(v.theta));
  v.y = static_cast<float>(v.y + u.translation * std::sin(v.theta));
}

// Paper 4.2: the V-particle's move, mapped through each M-particle's A, plus
// zero-mean Gaussian noise in translation and rotation.
void MotionModel::moveM(MParticleSet& m, std::size_t begin, std::size_t end, double v_heading, const Control& u,
                        Rng& rng) const
{
  const double new_heading = v_heading + u.rotation;
  const double old_dx = std::cos(v_heading), old_dy = std::sin(v_heading);
  const double new_dx = std::cos(new_heading), new_dy = std::sin(new_heading);
  for (std::size_t i = begin; i < end; ++i)
  {
    double l00, l01, l10, l11;
    if (m.affine_valid[i] == kFittedAffine)
    {
      l00 = m.affine[0][i];
      l01 = m.affine[1][i];
      l10 = m.affine[3][i];
      l11 = m.affine[4][i];
    }
    else
    {
      // No A yet: the rotation that takes the V heading onto the M heading.
      const double r = m.theta[i] - v_heading;
      l00 = std::cos(r);
      l01 = -std::sin(r);
      l10 = std::sin(r);
      l11 = std::cos(r);
    }
    // Heading change: the angle from the mapped old to the mapped new V direction.
    const double mapped_old_x = l00 * old_dx + l01 * old_dy, mapped_old_y = l10 * old_dx + l11 * old_dy;
    const double mapped_new_x = l00 * new_dx + l01 * new_dy, mapped_new_y = l10 * new_dx + l11 * new_dy;
    const double turn = std::atan2(mapped_old_x * mapped_new_y - mapped_old_y * mapped_new_x,
                                   mapped_old_x * mapped_new_x + mapped_old_y * mapped_new_y);
    m.theta[i] = static_cast<float>(m.theta[i] + turn + rng.gaussian(noise_rotation_));
    m.x[i] = static_cast<float>(m.x[i] + u.translation * mapped_new_x + rng.gaussian(noise_translation_));
    m.y[i] = static_cast<float>(m.y[i] + u.translation * mapped_new_y + rng.gaussian(noise_translation_));
    // A frontal shape stays frontal (the frontal hypotheses are kept apart
    // from the oblique ones: particle_seeder.cpp, drawShape).
    if (noise_shape_ > 0.0 && !(m.shape[0][i] == kFrontalShape[0] && m.shape[1][i] == kFrontalShape[1] &&
                                m.shape[2][i] == kFrontalShape[2]))
    {
      const float e1 = static_cast<float>(rng.gaussian(noise_shape_)), e2 = static_cast<float>(rng.gaussian(noise_shape_));
      float shape[3] = {m.shape[0][i], m.shape[1][i], m.shape[2][i]};
      diffuseShape(e1, e2, shape);
      for (int k = 0; k < 3; ++k)
        m.shape[k][i] = shape[k];
    }
  }
}
}  // namespace amcr
