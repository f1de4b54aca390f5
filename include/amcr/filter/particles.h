// Particle state of Radial-AMCR (spec "State"), kept contiguous: the
// M-particles are a structure of arrays, and the M-particles of V-particle v
// are the index range [v * per_v, (v + 1) * per_v) (the map R^-1(v)).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "amcr/scan/radial_scan.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
/// A V-particle's measurement z_k: its 8 feature-ray distances (theta + k * 45
/// deg) in input px, 0 where a ray met no edge.
struct RaySignature
{
  float distance[kFeatureRays] = {0, 0, 0, 0, 0, 0, 0, 0};
  int valid_rays() const;
};

/// A place of the image the feature rays are read at: position (px) and heading (rad).
struct RayPlace
{
  float x = 0.f;
  float y = 0.f;
  float theta = 0.f;
};

/// Scans the 8 feature rays of the pose (x, y, theta): theta + k * 45 deg.
void scanFeatureRays(const RadialScanner& scanner, float x, float y, float theta, RayHit hits[kFeatureRays]);

/// The signature of scanned feature rays: each valid hit's distance (at
/// least 1e-3 px), 0 for a ray that met no edge.
RaySignature raySignature(const RayHit hits[kFeatureRays]);

/// The 8 feature rays the view from (x, y) with heading theta would show
/// seen frontally, if the image is a view of shape `shape` (xx, xy, yy; the
/// symmetric part of an image -> table map, det 1; corrected_scan.h): the
/// image is scanned along P^-1 u_k, where u_0 is the heading mapped by P and
/// u_k is u_0 turned by k * 45 deg, and each distance is mapped back by P.
/// Ray 0 is the heading itself, so a place the index finds for them gives
/// the M-particle's heading directly (the table direction of u_0).
RaySignature unsquashedFeatureRays(const RadialScanner& scanner, float x, float y, float theta, const float shape[3]);

/// One interpretation a V-particle's M-particles hold: the most likely
/// M-particle of a cluster, and the share of the V-particle's M-particles in
/// the cluster.
struct CompetingHypothesis
{
  int prototype = -1;
  float x = 0.f;  ///< table px of the M-particle
  float y = 0.f;
  /// Where its V-particle was when the hypothesis was taken, input px: the
  /// image point that (x, y) corresponds to.
  float image_x = 0.f;
  float image_y = 0.f;
  /// Linear part of its affine A (image -> table), row-major 2x2.
  float linear[4] = {1.f, 0.f, 0.f, 1.f};
  float share = 0.f;  ///< of the V-particle's M-particles, within the cluster radius
};

/// The clusters a V-particle is deciding between (at most kMaxCompeting;
/// discriminative_attention.h).
struct CompetingHypotheses
{
  static constexpr int kMaxCompeting = 3;
  int count = 0;
  CompetingHypothesis hypothesis[kMaxCompeting];
};

/// A V-particle: a pose in the input image plus its evidence record.
struct VParticle
{
  float x = 0.f;      ///< input px
  float y = 0.f;      ///< input px
  float theta = 0.f;  ///< heading, rad (x right, y down)
  /// Sum of log evidence (log of the mean M-particle likelihood) since the
  /// last V-resampling, and how many iterations it covers.
  double log_evidence_sum = 0.0;
  int evidence_count = 0;
  int age = 0;  ///< iterations since this V-particle was seeded
  RaySignature rays;  ///< the last measurement
  /// The clusters its M-particles held before its last move, when two or
  /// more compete (count 0 otherwise).
  CompetingHypotheses competing;
  /// Whether its last move was chosen to decide between them (else the
  /// exploration policy chose it).
  bool discriminating = false;
};

/// Log V-weight that the verification of a V-particle's interpretation adds
/// to its evidence (paper 4.3, attention feedback).
struct EvidenceBonus
{
  int v = -1;  ///< index of the V-particle
  double log_weight = 0.0;
};

/// Where the optical flow takes one V-particle into the current frame.
struct VParticleMove
{
  enum class Kind
  {
    kWithTrack,  ///< moved with the track it lies on: position and heading
    kWithFlow,   ///< moved by the Lucas-Kanade flow at its position: position only
    kLost,       ///< its flow failed: it is seeded afresh
  };
  Kind kind = Kind::kLost;
  float x = 0.f;      ///< input px of the current frame (not kLost)
  float y = 0.f;
  float theta = 0.f;  ///< rad (kWithTrack only)
};

/// The M-particles of one V-particle: indices [begin, end) of the set.
struct MRange
{
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

/// Whether MParticleSet::affine holds an affine for one M-particle.
enum AffineState : std::uint8_t
{
  kNoAffine = 0,      ///< nothing: the heading alone orients the lookups
  kFittedAffine = 1,  ///< A of the last relational update (paper 4.1)
};

/// All M-particles of all V-particles.
struct MParticleSet
{
  std::vector<float> x;       ///< prototype pose, table px
  std::vector<float> y;       ///< table px
  std::vector<float> theta;   ///< rad
  std::vector<int> prototype; ///< index into the memory
  /// A: input image -> prototype table, row-major 2x3 (paper: the affine of
  /// the relational particle (v, m), stored in m).
  std::array<std::vector<float>, 6> affine;
  std::vector<std::uint8_t> affine_valid;  ///< an AffineState
  /// ray_correspondence affine: the view shape the M-particle assumes, the
  /// symmetric part P of A = R P scaled to det 1, row-major (xx, xy, yy);
  /// (1, 0, 1) for a frontal view. Part of its state like the heading: drawn
  /// at seeding, diffused by the motion model, kept through resampling
  /// (corrected_scan.h).
  std::array<std::vector<float>, 3> shape;
  std::vector<float> log_likelihood;  ///< log p(z_k | m) of the last update
  /// log of the importance weight a new M-particle's proposal gives it, the
  /// seeding density over the proposal's (proposal_index.h; 0 but for a
  /// particle drawn since the last M-resampling with the index on).
  std::vector<float> log_proposal;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
  /// Copies particle `from` onto `to` (either may be in any range).
  void copy(std::size_t from, std::size_t to);
  /// Copies particle `from` of `source` onto `to` of this set.
  void copyFrom(const MParticleSet& source, std::size_t from, std::size_t to);
  /// Copies particles [begin, end) of `source` onto the same indices here.
  void copyRange(const MParticleSet& source, std::size_t begin, std::size_t end);
};
}  // namespace amcr
