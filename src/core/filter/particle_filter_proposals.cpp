// The particle filter's proposals from the index (spec "Beyond the paper"):
// the places the proposal and profile indexes find for a V-particle's rays,
// the new M-particles drawn at them, and the importance weight of each.
#include <algorithm>
#include <cmath>
#include <vector>

#include "amcr/filter/particle_filter.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
// Mixture proposal (Thrun, Fox, Burgard & Dellaert's Mixture-MCL; Lenser &
// Veloso's sensor resetting): a share of the new M-particles where the index
// finds table rays like the V-particle's. Its importance weight
// (logProposalWeight) raised to proposal_correction: 1 keeps the filter a
// correct SIR for the paper's uniform seeding, 0 lets a proposed particle
// compete by its likelihood alone (sensor resetting); with the index off
// nothing is drawn and the weight is 1.
void ParticleFilter::seedM(MParticleSet& set, std::size_t index, int prototype, const VParticle& v,
                           VWorkspace& work) const
{
  const double share = work.candidates.empty() ? 0.0 : params_.index_share;
  if (share > 0.0 && work.rng.uniform() < share)
    seedAtCandidate(set, index, work.candidates[work.rng.index(work.candidates.size())], work.rng);
  else
    seedUniform(set, index, prototype, v, work.rng);
  set.log_proposal[index] = share > 0.0 && params_.proposal_correction > 0.0
                                ? static_cast<float>(params_.proposal_correction) *
                                      logProposalWeight(set, index, share, work.candidates)
                                : 0.f;
}

namespace
{
/// Position spread of an M-particle drawn at an index place: about the half
/// stride between indexed points, table px.
double candidateSpread(int stride) { return std::max(0.5, 0.5 * stride); }
}  // namespace

void ParticleFilter::seedAtCandidate(MParticleSet& set, std::size_t index, const ProposalCandidate& c,
                                     Rng& rng) const
{
  const Prototype& p = (*memory_)[c.prototype];
  const double spread = candidateSpread(params_.index_stride);
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
float ParticleFilter::logProposalWeight(const MParticleSet& set, std::size_t index, double share,
                                        const std::vector<ProposalCandidate>& candidates) const
{
  const int p = set.prototype[index];
  const double uniform = seedingProbability(p) / std::max<std::size_t>(1, (*memory_)[p].interior().size());
  const double spread = candidateSpread(params_.index_stride);
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

// The index holds frontal views only (proposal_index.h): a V-particle on an
// oblique view finds its true place only when its rays are read as the
// frontal view would show them. So besides its own rays it asks once more
// per iteration under a view shape drawn as an oblique M-particle's is, and
// the candidates are shared as the view shapes of new M-particles are:
// oblique_share of them from that query (a place found that way seeds its
// M-particle with that shape), the rest from its own rays. Not merged by
// descriptor distance: a squashed reading fits wrong places more closely too
// (one more degree of freedom), and crowded out the frontal ones.
void ParticleFilter::findCandidates(const VParticle& v, const RadialScanner& scanner, VWorkspace& work) const
{
  work.candidates.clear();
  if (!index_)
    return;
  const bool oblique_views = params_.ray_correspondence == RayCorrespondence::kAffine &&
                             params_.max_anisotropy > 1.0 && params_.oblique_share > 0.0;
  const int oblique_count =
      oblique_views ? std::min(params_.index_candidates - 1,
                               static_cast<int>(std::lround(params_.oblique_share * params_.index_candidates)))
                    : 0;
  const int frontal_count = params_.index_candidates - oblique_count;
  work.candidates = frontalCandidates(v, scanner, frontal_count);
  // The profile index's few best stand for all frontal_count: the share of
  // frontal and oblique candidates (the draw picks one uniformly) stays.
  for (std::size_t i = 0; !work.candidates.empty() && work.candidates.size() < static_cast<std::size_t>(frontal_count);
       ++i)
    work.candidates.push_back(work.candidates[i]);
  if (oblique_count == 0)
    return;
  float shape[3];
  drawObliqueShape(work.rng, shape);
  for (ProposalCandidate c :
       index_->query(unsquashedFeatureRays(scanner, v.x, v.y, v.theta, shape), oblique_count))
  {
    std::copy(shape, shape + 3, c.shape);
    work.candidates.push_back(c);
  }
}

std::vector<ProposalCandidate> ParticleFilter::frontalCandidates(const VParticle& v, const RadialScanner& scanner,
                                                                 int count) const
{
  if (!index_)
    return {};
  RadialProfile profile;
  if (profile_index_ && scanProfile(scanner, v.x, v.y, v.theta, profile))
  {
    std::vector<ProposalCandidate> found =
        profile_index_->query(*memory_, profile, params_.index_candidates, kProfileCandidates);
    if (!found.empty())
      return found;
  }
  return index_->query(v.rays, count);
}
}  // namespace amcr
