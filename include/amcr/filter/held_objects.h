// The objects the tracker holds, as the particle filter sees them (spec
// "Attention that moves on"): what they show is explained, so no V-particle
// starts inside one (inhibition of return) and V-resampling leaves each only
// a few V-particles; and they are the scene's context, so a share of the new
// M-particles is drawn in their prototypes (paper 3.6's context priors).
// Reads AttentionParams' held_v_particles and scene_prior_share.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/base/random.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_prior.h"

namespace amcr
{
/// An object that the tracker holds: what attention may leave alone.
struct HeldObject
{
  int prototype = -1;                ///< index into the memory
  std::vector<cv::Point2d> outline;  ///< px of the filter's image
  /// The V-particles that support it (V indices, valid until the next
  /// V-resampling), wherever they are.
  std::vector<int> v_particles;
};

class HeldObjects
{
public:
  explicit HeldObjects(const AttentionParams& attention);

  /// Holds `held` (replacing the last ones) in an image of `image_size`;
  /// only their prototypes whose `prior` is not 0 lean the seeding. None
  /// is held when `image_size` is empty. InputError, before anything
  /// changes, for a prototype index outside a memory of `prototypes`.
  void set(const std::vector<HeldObject>& held, const cv::Size& image_size, const PrototypePrior& prior,
           std::size_t prototypes);
  void clear();

  /// Index (in the last set()) of the held object whose outline's convex
  /// hull holds (x, y), or -1.
  int at(float x, float y) const;
  /// A uniform place in an image of `image_size` outside the held objects
  /// (inside one only when they cover the whole image).
  cv::Point2f drawFreePlace(const cv::Size& image_size, Rng& rng) const;
  /// The prototype of a new M-particle whose prior slot is `slot`: with
  /// probability scene_prior_share (when objects are held) a held object's
  /// prototype, else `slot`.
  int scenePrototype(int slot, Rng& rng) const;
  /// The probability that a new M-particle is in prototype p: `prior`
  /// mixed with the held objects' prototypes (scenePrototype).
  double seedingProbability(int p, const PrototypePrior& prior) const;
  /// The V-particles V-resampling carries over unchanged: of those on each
  /// held object (inside its hull or supporting it), the held_v_particles
  /// with the highest `log_weights`. Every V-particle on a held object gets
  /// log weight -inf (it is not drawn).
  std::vector<int> keep(const std::vector<VParticle>& v, std::vector<double>& log_weights) const;

private:
  int keep_per_object_;       // held_v_particles
  double scene_prior_share_;  // scene_prior_share
  cv::Mat mask_;  // CV_16UC1 of the image: 0 free, k + 1 inside held object k's hull; empty: none held
  std::vector<std::vector<int>> supporters_;  // each held object's V-particles (one entry per held object)
  std::vector<int> prototypes_;               // the held objects' prototypes whose prior is not 0
};
}  // namespace amcr
