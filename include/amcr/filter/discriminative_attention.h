// Attention that discriminates (the paper's section 4.3, "a feedback control
// that would move the V-particle to a part that best discriminates M2 and
// M3"): when a V-particle's M-particles hold two or more clusters, its next
// move goes where their interpretations disagree most, instead of where the
// exploration policy would take it.
//
// Each cluster predicts the V-particle's next scan from its prototype's
// lookup table alone: its most likely M-particle's affine A maps the move
// into the table, and the table holds the rays there, so a prediction reads
// no image pixel. A move is scored by the expected log-likelihood ratio
// between the clusters' predicted scans (eqs. 5-6 applied to one prediction
// as if the other were observed), weighted by the clusters' shares: the
// information the scan there is expected to give about which cluster is
// right.
#pragma once

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/filter/motion_model.h"
#include "amcr/filter/particles.h"
#include "amcr/filter/ray_divergence.h"

namespace amcr
{
class DiscriminativePlaces;
class ObservationModel;
class Prototype;
class PrototypeMemory;

/// The distinct interpretations among M-particles [r.begin, r.end) of `m`:
/// greedily, the most likely M-particle with a fitted affine that lies in no
/// earlier one's cluster (another prototype, or farther than `radius` table
/// px), up to kMaxCompeting; each with the share of the range within
/// `radius` of it in its prototype. Only those holding at least `min_share`
/// of the range are kept.
/// Every hypothesis is anchored at the V-particle's place (v_x, v_y).
CompetingHypotheses competingHypotheses(const MParticleSet& m, const MRange& r, float v_x, float v_y, float radius,
                                        float min_share);

/// Whether the V-particle whose M-particles hold `h` is deciding between
/// look-alikes: its most likely cluster holds at least `converged_share` of
/// them (it has found a shape) and another prototype competes with it (it
/// has not yet found which). Before that the V-particle is still searching,
/// and exploration serves it better than discrimination (measured on the
/// `oblique` suite, where targets are found late).
bool decidingBetweenLookAlikes(const CompetingHypotheses& h, float converged_share);

/// The table -> input image affine of hypothesis `h`: its M-particle's A,
/// inverted about the place it was anchored at. False when A is singular.
bool hypothesisTableToImage(const CompetingHypothesis& h, Affine& table_to_image);

/// The 8 feature rays, image px (0: no edge), that hypothesis `h` predicts
/// for its V-particle moved by (dx, dy) image px to heading `theta`: the
/// move mapped into the table by h's affine, the rays' image directions
/// mapped to table directions, each table distance mapped back to image px.
/// Returns false when the moved place lies outside the prototype's table.
bool predictedRays(const Prototype& prototype, const CompetingHypothesis& h, float dx, float dy, float theta,
                   RaySignature& rays);

/// A candidate move and what it is expected to tell.
struct DiscriminativeMove
{
  Control control;
  double gain = 0.0;       ///< share-weighted divergence of the predicted scans, nats (a place's, toward one)
  bool to_place = false;   ///< a step toward a precomputed discriminative place
};

/// Chooses the move of a V-particle that is deciding between clusters.
class DiscriminativeMoveChooser
{
public:
  /// `step`: the exploration step (v_step), px; the candidate steps are 1
  /// and 2 of it. `min_gain`: the least gain, nats, for which a move is
  /// chosen.
  DiscriminativeMoveChooser(double step, double min_gain);

  /// The move of `v` for the hypotheses `h`. With `places` (null: none),
  /// when the leading cluster's prototype and the first other prototype
  /// competing with it are a look-alike pair with places, and the nearest
  /// of them (mapped into the image by the leading cluster's affine) lies
  /// beyond 2 steps: 1 or 2 steps toward it, along the feature ray nearest
  /// its direction (or a neighbour) that leaves room. Else the best of the
  /// candidate moves (turn by k * 45 deg, then move 1 or 2 steps; only as
  /// far as v's last scan leaves room before an edge, and inside an image
  /// of `image_size`) by the clusters' predicted scans. False when fewer
  /// than two compete, no candidate keeps every hypothesis inside its
  /// table, or the best gain is below min_gain: the V-particle then
  /// explores as the policy says.
  bool choose(const VParticle& v, const CompetingHypotheses& h, const PrototypeMemory& memory,
              const ObservationModel& observation, const cv::Size& image_size, const DiscriminativePlaces* places,
              DiscriminativeMove& best) const;

private:
  /// The step toward the nearest place of the leading pair, when it lies
  /// beyond 2 steps (choose()).
  bool headForPlace(const VParticle& v, const CompetingHypotheses& h, const DiscriminativePlaces& places,
                    const cv::Size& image_size, DiscriminativeMove& best) const;

  double step_;
  double min_gain_;
};
}  // namespace amcr
