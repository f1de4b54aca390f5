// Result extraction (spec "Output"): from each V-particle's M-particles to
// clusters, and from agreeing V-particles to objects.
#pragma once

#include <vector>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/filter/particles.h"

namespace amcr
{
/// The mode of a V-particle's M-particles about its most likely one.
struct LikeliestMode
{
  int prototype = -1;            ///< -1: no measured M-particle with a fitted A
  cv::Point2f mean;              ///< table px of that prototype
  float log_likelihood = 0.f;    ///< of the most likely M-particle (eq. 5-6, last update)
  Affine image_to_table;         ///< mean A of the mode's M-particles with a valid A
  bool has_affine = false;
};

/// The densest M-cluster of one V-particle.
struct VParticleCluster
{
  int v = -1;              ///< index of the V-particle
  int prototype = -1;      ///< prototype of the cluster
  cv::Point2f mean;        ///< cluster mean, table px of that prototype
  float share = 0.f;       ///< share of the V-particle's M-particles in the cluster
  Affine image_to_table;   ///< mean A of the cluster's M-particles with a valid A
  bool has_affine = false;
  /// Focused enough to stand for its V-particle's interpretation: it holds
  /// at least cluster_min_share of the V-particle's M-particles. Set by
  /// dominantClusters, the one place of the extraction that reads
  /// cluster_min_share; everything after reads this.
  bool converged = false;
  /// The mode about the most likely M-particle (result extraction: a fit
  /// starts there for the most likely V-particles that have not converged);
  /// found only when params.likeliest_fits asks for it.
  LikeliestMode likeliest;
};

/// Finds the densest cluster among M-particles [begin, end): a mean shift of
/// `radius` table px from the most likely particle of each prototype, most
/// populated prototype first, keeping the mode with the most members (a tight
/// cluster in one prototype wins over more particles spread over another).
/// With `with_likeliest`, also the mode about the most likely particle
/// (VParticleCluster::likeliest), which only likeliest_fits reads.
VParticleCluster dominantCluster(const MParticleSet& m, std::size_t begin, std::size_t end, int prototype_count,
                                 double radius, bool with_likeliest = false);

/// The dominant cluster of every V-particle (index = V index) of `v`, whose
/// M-particles in `m` are `ranges` (one per V-particle): of radius
/// params.cluster_radius, converged at params.cluster_min_share.
std::vector<VParticleCluster> dominantClusters(const std::vector<VParticle>& v, const MParticleSet& m,
                                               const std::vector<MRange>& ranges, int prototype_count,
                                               const ExtractionParams& params);

/// V-particles that agree on one object: the same prototype and affines that
/// map each other's correspondences within `group_tolerance` input px.
struct ObjectHypothesis
{
  int prototype = -1;
  std::vector<int> members;  ///< indices into the cluster list
  Affine table_to_image;     ///< fitted to the members' correspondences
};

/// Groups converged clusters, largest share first, within
/// params.group_tolerance; every group of at least `min_members` members
/// becomes a hypothesis with an affine fitted robustly to all its
/// correspondences (to the seed's own when they spread less than twice
/// params.cluster_radius).
std::vector<ObjectHypothesis> groupClusters(const std::vector<VParticle>& v,
                                            const std::vector<VParticleCluster>& clusters,
                                            const ExtractionParams& params, int min_members);
}  // namespace amcr
