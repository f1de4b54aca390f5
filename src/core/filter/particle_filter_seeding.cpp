// Where the particle filter's new particles start: the V-particles at
// places enclosed by edges, each with its M-particles spread over the
// prototypes by the prior (paper 3.6), uniformly inside a prototype with the
// heading from the heading proposal and, with ray_correspondence affine, a
// view shape. The share drawn from the index is in
// particle_filter_proposals.cpp.
#include <cmath>

#include "amcr/base/parallel_for.h"
#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/heading_proposal.h"
#include "amcr/filter/particle_filter.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr float kMinSeedRayLength = 4.f;  // px: shorter rays at a seed place mean texture, not a region
}  // namespace

void ParticleFilter::seed(const RadialScanner& scanner)
{
  if (scanner.image().size() != image_size_)
    setHeldObjects({});  // outlines of another image size
  image_size_ = scanner.image().size();
  const std::size_t per_v = static_cast<std::size_t>(mParticlesPerV());
  v_.assign(params_.num_v_particles, VParticle());
  m_count_.assign(v_.size(), static_cast<int>(per_v));
  m_.resize(v_.size() * per_v);
  m_scratch_.resize(m_.size());
  parallelFor(static_cast<int>(v_.size()), resolveThreads(params_.num_threads), [&](int i) {
    seedVAndM(v_[i], m_, i * per_v, (i + 1) * per_v, scanner, work_[i]);
  });
  leading_.clear();
}

void ParticleFilter::seedVAndM(VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end,
                               const RadialScanner& scanner, VWorkspace& work)
{
  seedV(v, scanner, work.rng);
  findCandidates(v, scanner, work);
  seedMRange(set, begin, end, v, work);
}

// Spec "Where V-particles start matters": prefer places enclosed by edges
// (inside closed regions), trying `seed_attempts` random places.
void ParticleFilter::seedV(VParticle& v, const RadialScanner& scanner, Rng& rng)
{
  int best_enclosure = -1;
  for (int attempt = 0; attempt < params_.seed_attempts; ++attempt)
  {
    const cv::Point2f place = drawFreePlace(rng);
    const float x = place.x, y = place.y;
    const float theta = static_cast<float>(rng.uniform(-M_PI, M_PI));
    // Rays that meet an edge, but not at once: texture is not a region.
    RayHit hits[kFeatureRays];
    scanFeatureRays(scanner, x, y, theta, hits);
    int enclosure = 0;
    for (const RayHit& hit : hits)
      enclosure += (hit.valid && hit.distance >= kMinSeedRayLength) ? 1 : 0;
    if (enclosure > best_enclosure)
    {
      best_enclosure = enclosure;
      v = VParticle();
      v.x = x;
      v.y = y;
      v.theta = theta;
      v.rays = raySignature(hits);
    }
    if (enclosure >= params_.seed_enclosure_rays)
      break;
  }
}

void ParticleFilter::seedMRange(MParticleSet& set, std::size_t begin, std::size_t end, const VParticle& v,
                                VWorkspace& work) const
{
  for (std::size_t j = 0; j < end - begin; ++j)
    seedM(set, begin + j, scenePrototype(prior_.slots()[j], work.rng), v, work);
}

// A new M-particle has no affine yet, and the likelihood of all rays invalid.
void ParticleFilter::clearMeasurement(MParticleSet& set, std::size_t index) const
{
  for (auto& a : set.affine)
    a[index] = 0.f;
  set.affine_valid[index] = kNoAffine;
  set.log_likelihood[index] = static_cast<float>(kFeatureRays * observation_.logInvalid());
}

// A uniform position inside the prototype; the heading from the proposal
// (heading_proposal.h) when the V-particle sees enough edges, else uniform.
// With ray_correspondence affine, first a view shape, which the heading
// proposal then matches the rays under.
void ParticleFilter::seedUniform(MParticleSet& set, std::size_t index, int prototype, const VParticle& v,
                                 Rng& rng) const
{
  const Prototype& p = (*memory_)[prototype];
  const cv::Point& at = p.interior()[rng.index(p.interior().size())];
  set.x[index] = static_cast<float>(at.x);
  set.y[index] = static_cast<float>(at.y);
  int bin = -1;
  if (params_.ray_correspondence == RayCorrespondence::kAffine)
  {
    if (drawShape(set, index, rng))
    {
      const float shape[3] = {set.shape[0][index], set.shape[1][index], set.shape[2][index]};
      bin = bestHeadingBin(p, at.x, at.y, v.rays, RayOffsets(shape, v.theta));
    }
    else
    {
      bin = bestHeadingBin(p, at.x, at.y, v.rays);
    }
  }
  else
  {
    for (int k = 0; k < 3; ++k)
      set.shape[k][index] = kFrontalShape[k];
    bin = bestHeadingBin(p, at.x, at.y, v.rays);
  }
  const double heading = bin >= 0 ? binToAngle(bin) : rng.uniform(-M_PI, M_PI);
  set.theta[index] = static_cast<float>(wrapAngle(heading));
  set.prototype[index] = prototype;
  clearMeasurement(set, index);
}

// The view shape of a new M-particle: frontal, or for oblique_share of
// them anisotropy log-uniform in [1, max_anisotropy] along a uniform axis
// (views are often near frontal, and those must not lose their particles to
// the search). The scale is left to the triangle fit.
bool ParticleFilter::drawShape(MParticleSet& set, std::size_t index, Rng& rng) const
{
  float shape[3] = {kFrontalShape[0], kFrontalShape[1], kFrontalShape[2]};
  const bool oblique =
      params_.max_anisotropy > 1.0 && params_.oblique_share > 0.0 && rng.uniform() < params_.oblique_share;
  if (oblique)
    drawObliqueShape(rng, shape);
  for (int k = 0; k < 3; ++k)
    set.shape[k][index] = shape[k];
  return oblique;
}

void ParticleFilter::drawObliqueShape(Rng& rng, float shape[3]) const
{
  // The axis first, then the anisotropy, in two statements: the order of a
  // call's arguments is unspecified (this is the order GCC took).
  const float axis = static_cast<float>(rng.uniform(0.0, M_PI));
  const float anisotropy = static_cast<float>(std::exp(rng.uniform(0.0, std::log(params_.max_anisotropy))));
  obliqueShape(anisotropy, axis, shape);
}
}  // namespace amcr
