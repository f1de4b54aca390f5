// The measurement of one V-particle: its ray scans, then the update of its
// relational particles (v, m) by the observation model (the triangle affine
// of paper 4.1 and the likelihood of eqs. 5-6, in relational_update.h).
#include "amcr/filter/particle_filter.h"
#include "amcr/filter/relational_update.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
void ParticleFilter::measure(int v_index, const RadialScanner& scanner)
{
  VParticle& v = v_[v_index];
  // The V-particle's measurement: 8 feature rays (k * 45 deg) and the two
  // further triangle rays (120, 240 deg); ray 0 serves both.
  float v_dist[kFeatureRays + 2];
  bool v_valid[kFeatureRays + 2];
  RayHit hits[kFeatureRays];
  scanFeatureRays(scanner, v.x, v.y, v.theta, hits);
  for (int k = 0; k < kFeatureRays; ++k)
  {
    v_dist[k] = hits[k].distance;
    v_valid[k] = hits[k].valid;
  }
  v.rays = raySignature(hits);
  VWorkspace& work = work_[v_index];
  findCandidates(v, scanner, work);  // for the M-particles this iteration seeds
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const RayHit hit = scanner.scanAngle(v.x, v.y, v.theta + t * kTriangleBinStep * kBinAngle);
    v_dist[kFeatureRays + t - 1] = hit.distance;
    v_valid[kFeatureRays + t - 1] = hit.valid;
  }

  // Spec "Motion model": an M-particle that has left its prototype is
  // re-seeded, in index order, before the update.
  const MRange r = mRange(v_index);
  for (std::size_t i = r.begin; i < r.end; ++i)
    if (!insideTable((*memory_)[m_.prototype[i]], nearestTablePixel(m_.x[i], m_.y[i])))
      seedM(m_, i, m_.prototype[i], v, work);
  // The relational update of paper 4.1 and eqs. 5-6 (ObservationModel::measure).
  observation_.measure(*memory_, rayEnds(v, v_dist, v_valid), m_, r.begin, r.end);
}
}  // namespace amcr
