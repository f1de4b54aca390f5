#include "amcr/filter/particle_seeder.h"

#include <algorithm>
#include <cmath>

#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/heading_proposal.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr float kMinSeedRayLength = 4.f;  // px: shorter rays at a seed place mean texture, not a region

/// Position spread of an M-particle drawn at an index place: about the half
/// stride between indexed points, table px.
double candidateSpread(int stride) { return std::max(0.5, 0.5 * stride); }
}  // namespace

ParticleSeeder::ParticleSeeder(const ResamplingParams& resampling, const ProposalParams& proposals,
                               const ObservationParams& observation, double log_invalid)
  : seed_attempts_(resampling.seed_attempts)
  , seed_enclosure_rays_(resampling.seed_enclosure_rays)
  , index_share_(proposals.index_share)
  , proposal_correction_(proposals.proposal_correction)
  , index_stride_(proposals.index_stride)
  , index_candidates_(proposals.index_candidates)
  , ray_correspondence_(observation.ray_correspondence)
  , max_anisotropy_(observation.max_anisotropy)
  , oblique_share_(observation.oblique_share)
  , log_invalid_(log_invalid)
{
}

void ParticleSeeder::seedVAndM(VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end,
                               const RadialScanner& scanner, const SeedingScene& scene, VWorkspace& work) const
{
  seedV(v, scanner, scene, work.rng);
  seedMOf(v, set, begin, end, scanner, scene, work);
}

void ParticleSeeder::seedVAndMAt(const RayPlace& place, VParticle& v, MParticleSet& set, std::size_t begin,
                                 std::size_t end, const RadialScanner& scanner, const SeedingScene& scene,
                                 VWorkspace& work) const
{
  RayHit hits[kFeatureRays];
  scanFeatureRays(scanner, place.x, place.y, place.theta, hits);
  v = VParticle();
  v.x = place.x;
  v.y = place.y;
  v.theta = place.theta;
  v.rays = raySignature(hits);
  seedMOf(v, set, begin, end, scanner, scene, work);
}

void ParticleSeeder::seedMOf(const VParticle& v, MParticleSet& set, std::size_t begin, std::size_t end,
                             const RadialScanner& scanner, const SeedingScene& scene, VWorkspace& work) const
{
  findCandidates(v, scanner, scene.memory, work);
  const std::vector<int>& slots = scene.memory.prior().slots();
  for (std::size_t j = 0; j < end - begin; ++j)
    seedM(set, begin + j, scene.held.scenePrototype(slots[j], work.rng), v, scene, work);
}

// Spec "Where V-particles start matters": prefer places enclosed by edges
// (inside closed regions), trying `seed_attempts` random places.
void ParticleSeeder::seedV(VParticle& v, const RadialScanner& scanner, const SeedingScene& scene, Rng& rng) const
{
  int best_enclosure = -1;
  for (int attempt = 0; attempt < seed_attempts_; ++attempt)
  {
    const cv::Point2f place = scene.held.drawFreePlace(scene.image_size, rng);
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
    if (enclosure >= seed_enclosure_rays_)
      break;
  }
}

// Mixture proposal (Thrun, Fox, Burgard & Dellaert's Mixture-MCL; Lenser &
// Veloso's sensor resetting): a share of the new M-particles where the index
// finds table rays like the V-particle's. Its importance weight
// (logProposalWeight) raised to proposal_correction: 1 keeps the filter a
// correct SIR for the paper's uniform seeding, 0 lets a proposed particle
// compete by its likelihood alone (sensor resetting); with the index off
// nothing is drawn and the weight is 1.
void ParticleSeeder::seedM(MParticleSet& set, std::size_t index, int prototype, const VParticle& v,
                           const SeedingScene& scene, VWorkspace& work) const
{
  const PrototypeMemory& memory = *scene.memory.memory();
  const double share = work.candidates.empty() ? 0.0 : index_share_;
  if (share > 0.0 && work.rng.uniform() < share)
    seedAtCandidate(set, index, work.candidates[work.rng.index(work.candidates.size())], memory, work.rng);
  else
    seedUniform(set, index, prototype, v, memory, work.rng);
  set.log_proposal[index] = share > 0.0 && proposal_correction_ > 0.0
                                ? static_cast<float>(proposal_correction_) *
                                      logProposalWeight(set, index, share, work.candidates, scene)
                                : 0.f;
}

void ParticleSeeder::clearMeasurement(MParticleSet& set, std::size_t index) const
{
  for (auto& a : set.affine)
    a[index] = 0.f;
  set.affine_valid[index] = kNoAffine;
  set.log_likelihood[index] = static_cast<float>(kFeatureRays * log_invalid_);
}

// A uniform position inside the prototype; the heading from the proposal
// (heading_proposal.h) when the V-particle sees enough edges, else uniform.
// With ray_correspondence affine, first a view shape, which the heading
// proposal then matches the rays under.
void ParticleSeeder::seedUniform(MParticleSet& set, std::size_t index, int prototype, const VParticle& v,
                                 const PrototypeMemory& memory, Rng& rng) const
{
  const Prototype& p = memory[prototype];
  const cv::Point& at = p.interior()[rng.index(p.interior().size())];
  set.x[index] = static_cast<float>(at.x);
  set.y[index] = static_cast<float>(at.y);
  int bin = -1;
  if (ray_correspondence_ == RayCorrespondence::kAffine)
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

void ParticleSeeder::seedAtCandidate(MParticleSet& set, std::size_t index, const ProposalCandidate& c,
                                     const PrototypeMemory& memory, Rng& rng) const
{
  const Prototype& p = memory[c.prototype];
  const double spread = candidateSpread(index_stride_);
  // x before y, in two statements: the order of evaluation of an expression's operands is unspecified.
  const double x = c.x + rng.gaussian(spread);
  const double y = c.y + rng.gaussian(spread);
  set.x[index] = static_cast<float>(std::min(std::max(x, 0.0), p.width() - 1.0));
  set.y[index] = static_cast<float>(std::min(std::max(y, 0.0), p.height() - 1.0));
  set.theta[index] = static_cast<float>(wrapAngle(binToAngle(c.bin) + rng.uniform(-0.5, 0.5) * kBinAngle));
  set.prototype[index] = c.prototype;
  for (int k = 0; k < 3; ++k)
    set.shape[k][index] = c.shape[k];  // the view the query assumed: the descriptor matches similarities of it
  clearMeasurement(set, index);
}

// The weight pi(x) / q(x) of a new M-particle x: pi is the paper's seeding
// density (prototype from the prior, position uniform over its interior),
// q = (1 - share) pi + share q_index, q_index the mean of Gaussian kernels at
// the candidates of x's prototype. The headings are proposed in both parts
// (by the candidate, by the heading proposal) and are not weighted, as before.
float ParticleSeeder::logProposalWeight(const MParticleSet& set, std::size_t index, double share,
                                        const std::vector<ProposalCandidate>& candidates,
                                        const SeedingScene& scene) const
{
  const int p = set.prototype[index];
  const double uniform = scene.held.seedingProbability(p, scene.memory.prior()) /
                         std::max<std::size_t>(1, (*scene.memory.memory())[p].interior().size());
  const double spread = candidateSpread(index_stride_);
  const double norm = 1.0 / (2.0 * M_PI * spread * spread * candidates.size());
  double kernel = 0.0;
  for (const ProposalCandidate& c : candidates)
  {
    if (c.prototype != p)
      continue;
    const double dx = set.x[index] - c.x, dy = set.y[index] - c.y;
    kernel += std::exp(-(dx * dx + dy * dy) / (2.0 * spread * spread));
  }
  const double mixture = (1.0 - share) * uniform + share * kernel * norm;
  return static_cast<float>(std::log(uniform) - std::log(mixture));
}

// The view shape of a new M-particle: frontal, or for oblique_share of
// them anisotropy log-uniform in [1, max_anisotropy] along a uniform axis
// (views are often near frontal, and those must not lose their particles to
// the search). The scale is left to the triangle fit.
bool ParticleSeeder::drawShape(MParticleSet& set, std::size_t index, Rng& rng) const
{
  float shape[3] = {kFrontalShape[0], kFrontalShape[1], kFrontalShape[2]};
  const bool oblique = max_anisotropy_ > 1.0 && oblique_share_ > 0.0 && rng.uniform() < oblique_share_;
  if (oblique)
    drawObliqueShape(rng, shape);
  for (int k = 0; k < 3; ++k)
    set.shape[k][index] = shape[k];
  return oblique;
}

void ParticleSeeder::drawObliqueShape(Rng& rng, float shape[3]) const
{
  // The axis first, then the anisotropy, in two statements: the order of a
  // call's arguments is unspecified (this is the order GCC took).
  const float axis = static_cast<float>(rng.uniform(0.0, M_PI));
  const float anisotropy = static_cast<float>(std::exp(rng.uniform(0.0, std::log(max_anisotropy_))));
  obliqueShape(anisotropy, axis, shape);
}

// The index holds frontal views only (proposal_index.h): a V-particle on an
// oblique view finds its true place only when its rays are read as the
// frontal view would show them. So besides its own rays it asks once more
// per iteration under a view shape drawn as an oblique M-particle's is, and
// the candidates are shared as the view shapes of new M-particles are:
// oblique_share of them from that query (a place found that way seeds its
// M-particle with that shape), the rest from its own rays. Not merged by
// descriptor distance: a squashed reading fits wrong places more closely too
// (one more degree of freedom), and crowded out the frontal ones.
void ParticleSeeder::findCandidates(const VParticle& v, const RadialScanner& scanner, const FilterMemory& memory,
                                    VWorkspace& work) const
{
  work.candidates.clear();
  const ProposalIndex* index = memory.index().get();
  if (!index)
    return;
  const bool oblique_views =
      ray_correspondence_ == RayCorrespondence::kAffine && max_anisotropy_ > 1.0 && oblique_share_ > 0.0;
  const int oblique_count =
      oblique_views
          ? std::min(index_candidates_ - 1, static_cast<int>(std::lround(oblique_share_ * index_candidates_)))
          : 0;
  const int frontal_count = index_candidates_ - oblique_count;
  work.candidates = frontalCandidates(v, scanner, memory, frontal_count);
  // The profile index's few best stand for all frontal_count: the share of
  // frontal and oblique candidates (the draw picks one uniformly) stays.
  for (std::size_t i = 0; !work.candidates.empty() && work.candidates.size() < static_cast<std::size_t>(frontal_count);
       ++i)
    work.candidates.push_back(work.candidates[i]);
  if (oblique_count == 0)
    return;
  float shape[3];
  drawObliqueShape(work.rng, shape);
  for (ProposalCandidate c : index->query(unsquashedFeatureRays(scanner, v.x, v.y, v.theta, shape), oblique_count))
  {
    std::copy(shape, shape + 3, c.shape);
    work.candidates.push_back(c);
  }
}

std::vector<ProposalCandidate> ParticleSeeder::frontalCandidates(const VParticle& v, const RadialScanner& scanner,
                                                                 const FilterMemory& memory, int count) const
{
  if (!memory.index())
    return {};
  RadialProfile profile;
  if (memory.profileIndex() && scanProfile(scanner, v.x, v.y, v.theta, profile))
  {
    std::vector<ProposalCandidate> found =
        memory.profileIndex()->query(*memory.memory(), profile, index_candidates_, kProfileCandidates);
    if (!found.empty())
      return found;
  }
  return memory.index()->query(v.rays, count);
}
}  // namespace amcr
