// The motion model Q of Radial-AMCR (paper 4.2): an M-particle performs its
// V-particle's movement mapped through its own affine A, plus Gaussian noise.
#pragma once

#include <cstddef>

#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/particles.h"

namespace amcr
{
/// The control u of a V-particle: first turn, then move forward.
struct Control
{
  double rotation = 0.0;     ///< rad
  double translation = 0.0;  ///< input px along the new heading
};

class MotionModel
{
public:
  /// Reads motion_noise_translation, motion_noise_rotation and, with
  /// `observation`'s ray_correspondence affine, motion_noise_shape.
  MotionModel(const MotionParams& motion, const ObservationParams& observation);
  /// The same from every parameter: for ParticleFilter and the tests, which
  /// hold the whole Params.
  explicit MotionModel(const Params& params) : MotionModel(params, params) {}
  MotionModel(double noise_translation, double noise_rotation, double noise_shape = 0.0);

  /// Moves V-particle `v` by `u` (turn, then move along the new heading).
  static void moveV(VParticle& v, const Control& u);

  /// Moves M-particles [begin, end) of `m` by `u` mapped through each one's A
  /// (paper 4.2). `v_heading` is the V-particle's heading before the move.
  /// A particle without a valid A maps the move by the rotation that takes
  /// the V heading onto its own. Noise: translation sigma in table px,
  /// rotation sigma in rad, and (when noise_shape > 0) the view shape
  /// diffused by diffuseShape of corrected_scan.h.
  void moveM(MParticleSet& m, std::size_t begin, std::size_t end, double v_heading, const Control& u,
             Rng& rng) const;

private:
  double noise_translation_;
  double noise_rotation_;
  double noise_shape_;
};
}  // namespace amcr
