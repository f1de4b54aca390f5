// The observation model O of Radial-AMCR (paper eqs. 5-6), in log space, and
// the relational update that applies it: for each M-particle m of a
// V-particle v, the triangle affine of (v, m) (paper 4.1) and log p(z_v | m).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"

namespace amcr
{
class PrototypeMemory;
struct MParticleSet;
struct RelationalAffine;
struct VRayEnds;

/// How the relational affine of a (V, M) pair is fitted and its deviations
/// measured (paper 4.1): the part of the observation model that is not the
/// ray likelihood of eqs. 5-6.
struct AffineFitRule
{
  float min_triangle_area = 0.f;  ///< px^2: a smaller triangle gives no affine
  float max_affine_scale = 0.f;   ///< an affine scaling more (or less than its inverse) is refused
  DeviationSpace deviation_space = DeviationSpace::kImage;
  RayCorrespondence ray_correspondence = RayCorrespondence::kAffine;
  int affine_refits = 0;          ///< re-estimates of A from the lookups along the fitted A

  explicit AffineFitRule(const ObservationParams& params);
};

class ObservationModel
{
public:
  /// Reads sigma_w, p_outlier, p_invalid, likelihood_form,
  /// min_triangle_area, max_affine_scale, deviation_space,
  /// ray_correspondence and affine_refits of `observation`, and the
  /// largest deviation of the mixture form, max_ray_length, of `scan`.
  ObservationModel(const ObservationParams& observation, const ScanParams& scan);
  /// The same from every parameter: for ParticleFilter and the tests, which
  /// hold the whole Params.
  explicit ObservationModel(const Params& params) : ObservationModel(params, params) {}

  /// log p(dw) of one valid ray with deviation dw px (paper eq. 5, or the
  /// normalised mixture): the definition the fast path tabulates.
  double logRay(double dw) const;

  /// log p_invalid, the term of a ray with no edge on either side (eq. 6).
  double logInvalid() const { return log_invalid_; }

  /// Fast log p(dw) from the squared deviation, interpolated in a table
  /// (equal to logRay within 1e-4).
  float logRayFromSquared(float dw_squared) const
  {
    const float index = dw_squared * inv_step_;
    if (!(index < static_cast<float>(table_.size() - 1)))
      return log_far_;
    const std::size_t i = static_cast<std::size_t>(index);
    const float f = index - static_cast<float>(i);
    return table_[i] + f * (table_[i + 1] - table_[i]);
  }

  /// The relational update (paper 3.6): for M-particles [begin, end) of `m`,
  /// all of V-particle `v`'s, writes affine and affine_valid (A, when the
  /// triangle fit of paper 4.1 is accepted) and log_likelihood (eq. 6; the
  /// value of 8 invalid rays when there is no A). Every one of them must lie
  /// inside its prototype's table (insideTable of relational_update.h; the
  /// caller re-seeds the others first), else InputError. Draws nothing.
  /// With ray_correspondence affine (corrected_scan.h) the lookups follow
  /// the affine, starting from each M-particle's view shape turned onto its
  /// heading, with affine_refits re-estimates of A (default none: each one
  /// lets every hypothesis fit itself to what it sees, and the likelihood
  /// tells them apart less; docs/how-it-works.md, "Oblique views: affine-corrected scans").
  /// The M-particles go through in blocks (observation_model_lanes.cpp),
  /// with the same output as measureReference: bitwise on x86-64 with GCC,
  /// within float rounding elsewhere (test_update_loop.cpp states the
  /// tolerance); with affine_refits above 0, measure is measureReference.
  void measure(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m, std::size_t begin,
               std::size_t end) const;

  /// The same update one M-particle at a time: the plain reference that the
  /// block path of measure is tested against (test_update_loop.cpp), and the
  /// path of affine_refits above 0.
  void measureReference(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m, std::size_t begin,
                        std::size_t end) const;

  /// log p(z_v | m) of eq. 6 over the 8 feature rays, for an M-particle at
  /// table pixel `at` and direction bin `bin` (raw: its table distances)
  /// whose relational affine is `affine`: p_invalid for a ray that is
  /// invalid in v or in the table, eq. 5 (tabulated) for the others.
  float logLikelihood(const VRayEnds& v, const std::uint8_t* raw, const cv::Point& at, int bin,
                      const RelationalAffine& affine) const;

  /// log p(z_v | m) of eq. 6 with the affine-corrected lookups: feature ray
  /// k is compared with the table ray of direction shape * d_k, where shape
  /// is the linear part of `affine` (image -> table).
  float correctedLogLikelihood(const VRayEnds& v, const std::uint8_t* raw, const cv::Point& at, const float shape[4],
                               const RelationalAffine& affine) const;

private:
  /// measure without refits: M-particles [begin, end), at most one block of
  /// them (observation_model_lanes.cpp).
  void measureBlock(const PrototypeMemory& memory, const VRayEnds& v, MParticleSet& m, std::size_t begin,
                    std::size_t end) const;

  /// Eq. 6 over v's feature rays; `table_end(k, x, y)` gives where table ray
  /// k ends (false: no edge).
  template <typename TableEnd>
  float featureRaysLogLikelihood(const VRayEnds& v, const RelationalAffine& affine, TableEnd table_end) const;

  double sigma_w_;
  double p_outlier_;
  double outlier_density_;
  double log_invalid_;
  float log_far_;
  float inv_step_;
  std::vector<float> table_;
  /// For measure's lanes: (table_[i], table_[i + 1] - table_[i]) for each
  /// cell i of table_, then (log_far_, 0) and (log p_invalid, 0), so that
  /// every ray term is start + fraction * slope (fraction 0 for the last two).
  std::vector<float> cell_start_slope_;
  AffineFitRule fit_;
};
}  // namespace amcr
