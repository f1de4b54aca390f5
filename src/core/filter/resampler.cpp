#include "amcr/filter/resampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/resampling.h"

namespace amcr
{
namespace
{
constexpr int kMaxCopiesPerV = 3;  // copies one V-particle may get at a V-resampling
// Share of the V-particles a reported object that is not held yet keeps at
// full V-weight: beyond it, the object's V-particles share that much weight.
constexpr double kObjectAttentionShare = 0.2;
// KLD-sampling's bins: about a cluster (cluster_radius 6 px) across, and
// the heading in 20 degree steps.
constexpr float kKldCell = 8.f;                                        // table px
constexpr float kKldAngle = static_cast<float>(20.0 * M_PI / 180.0);  // rad
}  // namespace

Resampler::Resampler(const ParticleCounts& counts, const ResamplingParams& resampling, const MotionParams& motion,
                     std::uint64_t seed)
  : kld_error_(counts.kld_error)
  , kld_z_(counts.kld_z)
  , min_m_particles_(counts.min_m_particles_per_v)
  , injection_fraction_(resampling.injection_fraction)
  , m_reseed_fraction_(resampling.m_reseed_fraction)
  , v_reseed_fraction_(resampling.v_reseed_fraction)
  , noise_translation_(motion.motion_noise_translation)
  , noise_rotation_(motion.motion_noise_rotation)
  , rng_(seed)
{
}

void Resampler::reset(std::uint64_t seed)
{
  rng_ = Rng(seed);
  leading_.clear();
  scratch_ = MParticleSet();
}

// SIR over all prototypes of R^-1(v) (paper 3.6), with a share re-seeded
// (ParticleSeeder::seedM: uniformly or from the index) and a share placed at
// the poses the leading hypotheses imply; the weights are the likelihoods
// times the proposal weights of the M-particles seeded since the last
// resampling. KLD-sampling sets the size of the next generation.
int Resampler::resampleM(const VParticle& v, MParticleSet& m, std::size_t begin, int count, int capacity,
                         const ParticleSeeder& seeder, const SeedingScene& scene, VWorkspace& work)
{
  std::vector<double>& weights = work.weights;
  weights.resize(count);
  float worst = std::numeric_limits<float>::infinity();
  for (int j = 0; j < count; ++j)
  {
    weights[j] = m.log_likelihood[begin + j] + m.log_proposal[begin + j];
    worst = std::min(worst, m.log_likelihood[begin + j]);
  }
  std::vector<int> picks;
  int next = capacity;
  if (kld_error_ > 0.0)
  {
    picks = systematicResampleLog(weights, capacity, work.rng);
    next = kldCount(m, picks, begin, capacity, work.kld_bins);
  }
  // The re-seeded share is one of the budget: a V-particle whose particles
  // agree keeps exploring at the rate of a spread one (up to a quarter of
  // its particles).
  int n_inject = leading_.empty() ? 0 : static_cast<int>(std::lround(injection_fraction_ * next));
  int n_reseed =
      std::min(static_cast<int>(std::lround(m_reseed_fraction_ * capacity)), next == capacity ? capacity : next / 4);
  n_inject = std::min(n_inject, next);
  n_reseed = std::min(n_reseed, next - n_inject);
  const int n_draw = next - n_inject - n_reseed;

  if (kld_error_ > 0.0)
  {
    // Thin the capacity picks systematically (they are sorted) to n_draw.
    for (int k = 0; k < n_draw; ++k)
      picks[k] = picks[static_cast<std::size_t>(k) * capacity / std::max(1, n_draw)];
    picks.resize(n_draw);
  }
  else
  {
    picks = systematicResampleLog(weights, n_draw, work.rng);
  }
  int k = 0;
  for (; k < n_draw; ++k)
  {
    scratch_.copyFrom(m, begin + picks[k], begin + k);
    scratch_.log_proposal[begin + k] = 0.f;  // weighted once, at this resampling
  }
  for (int j = 0; j < n_inject; ++j, ++k)
    injectM(v, leading_[j % leading_.size()], begin + k, worst, seeder, scene, work);
  for (int j = 0; j < n_reseed; ++j, ++k)
    seeder.seedM(scratch_, begin + k, scene.held.scenePrototype(scene.memory.prior().draw(work.rng), work.rng), v,
                 scene, work);
  m.copyRange(scratch_, begin, begin + next);
  return next;
}

// Fox 2003, eq. for n_chi: the number of particles that keeps the KL
// divergence between them and the posterior below kld_error with
// probability 1 - delta (kld_z its upper quantile), for k occupied bins of
// (prototype, position, heading); amcl's pf_resample_limit is the same bound.
int Resampler::kldCount(const MParticleSet& m, const std::vector<int>& picks, std::size_t begin, int capacity,
                        std::vector<std::uint64_t>& bins) const
{
  bins.clear();
  for (std::size_t k = 0; k < picks.size(); ++k)
  {
    if (k > 0 && picks[k] == picks[k - 1])
      continue;  // the same particle again (systematic picks come in runs): the same bin
    const std::size_t i = begin + picks[k];
    // Through int: a float cast straight to an unsigned type is undefined below 0.
    const auto cell = [](float value, float size) {
      return static_cast<std::uint64_t>(static_cast<std::uint16_t>(static_cast<int>(std::floor(value / size)) + 64));
    };
    const std::uint64_t bx = cell(m.x[i], kKldCell), by = cell(m.y[i], kKldCell), bt = cell(m.theta[i], kKldAngle);
    bins.push_back(static_cast<std::uint64_t>(m.prototype[i]) << 48 | bx << 32 | by << 16 | bt);
  }
  std::sort(bins.begin(), bins.end());
  const int occupied = static_cast<int>(std::unique(bins.begin(), bins.end()) - bins.begin());
  const int least = std::min(min_m_particles_, capacity);
  if (occupied <= 1)
    return least;
  const double k = occupied - 1;
  const double b = 2.0 / (9.0 * k);
  const double c = 1.0 - b + std::sqrt(b) * kld_z_;
  const double n = std::ceil(k / (2.0 * kld_error_) * c * c * c);
  return static_cast<int>(std::min<double>(capacity, std::max<double>(least, n)));
}

// The pose of v in the prototype that hypothesis h implies (its position,
// its heading mapped through h's affine), with motion noise; a pose outside
// the prototype is seeded instead.
void Resampler::injectM(const VParticle& v, const LeadingHypothesis& h, std::size_t index, float worst,
                        const ParticleSeeder& seeder, const SeedingScene& scene, VWorkspace& work)
{
  Rng& rng = work.rng;
  const Affine& a = h.image_to_table;
  const Prototype& p = (*scene.memory.memory())[h.prototype];
  const cv::Point2d at = applyAffine(a, cv::Point2d(v.x, v.y));
  if (at.x < 0 || at.y < 0 || at.x > p.width() - 1 || at.y > p.height() - 1)
  {
    seeder.seedM(scratch_, index, h.prototype, v, scene, work);
    return;
  }
  const double hx = std::cos(v.theta), hy = std::sin(v.theta);
  scratch_.x[index] = static_cast<float>(at.x + rng.gaussian(noise_translation_));
  scratch_.y[index] = static_cast<float>(at.y + rng.gaussian(noise_translation_));
  scratch_.theta[index] = static_cast<float>(std::atan2(a(1, 0) * hx + a(1, 1) * hy, a(0, 0) * hx + a(0, 1) * hy) +
                                             rng.gaussian(noise_rotation_));
  scratch_.prototype[index] = h.prototype;
  for (int e = 0; e < 6; ++e)
    scratch_.affine[e][index] = static_cast<float>(a(e / 3, e % 3));
  scratch_.affine_valid[index] = kFittedAffine;
  float fitted[6];
  float shape[3] = {kFrontalShape[0], kFrontalShape[1], kFrontalShape[2]};
  for (int e = 0; e < 6; ++e)
    fitted[e] = scratch_.affine[e][index];
  viewShape(fitted, shape);  // leaves the frontal shape for a degenerate affine
  for (int k = 0; k < 3; ++k)
    scratch_.shape[k][index] = shape[k];
  scratch_.log_likelihood[index] = worst;
  scratch_.log_proposal[index] = 0.f;
}

// Each V-particle's log V-weight: its mean log evidence since the last
// V-resampling. Attention is shared between objects: the V-particles of a
// reported object beyond a share of them (kObjectAttentionShare) share its
// weight, so that an object does not draw every V-particle away from the
// others and from the unexplored rest of the image.
std::vector<double> Resampler::attentionWeights(const std::vector<VParticle>& v,
                                                const std::vector<std::vector<int>>& object_v_particles) const
{
  const int n = static_cast<int>(v.size());
  std::vector<double> log_weights(n);
  for (int i = 0; i < n; ++i)
    log_weights[i] = v[i].evidence_count > 0 ? v[i].log_evidence_sum / v[i].evidence_count
                                             : -std::numeric_limits<double>::infinity();
  const double per_object = std::max(1.0, kObjectAttentionShare * n);
  for (const std::vector<int>& members : object_v_particles)
  {
    const double crowding = static_cast<double>(members.size()) / per_object;
    if (crowding > 1.0)
      for (int i : members)
        log_weights[i] -= std::log(crowding);
  }
  return log_weights;
}

VGeneration Resampler::drawV(const std::vector<VParticle>& v, const std::vector<std::vector<int>>& object_v_particles,
                             const HeldObjects& held)
{
  const int n = static_cast<int>(v.size());
  std::vector<double> log_weights = attentionWeights(v, object_v_particles);
  // A held object keeps a few V-particles; the rest, and the draws, go
  // where nothing is explained yet (inhibition of return, spec "Attention
  // that moves on").
  const std::vector<int> kept = held.keep(v, log_weights);
  const int n_free = n - static_cast<int>(kept.size());
  const bool any_weight = std::any_of(log_weights.begin(), log_weights.end(), [](double w) { return std::isfinite(w); });
  const int n_reseed =
      any_weight ? std::min(n_free, static_cast<int>(std::lround(v_reseed_fraction_ * n_free))) : n_free;
  const int n_draw = n_free - n_reseed;
  const std::vector<int> picks = systematicResampleLog(log_weights, n_draw, rng_);

  // The kept V-particles first, then the draws: a V-particle gets at most
  // kMaxCopiesPerV copies per resampling, so that attention cannot collapse
  // onto one region in a few rounds; the slots left over are seeded afresh.
  VGeneration next;
  next.source.assign(n, -1);
  std::vector<int> copies(n, 0);
  int slot = 0;
  for (int i : kept)
  {
    next.source[slot++] = i;
    ++copies[i];
  }
  for (int k = 0; k < n_draw; ++k, ++slot)
    if (copies[picks[k]] < kMaxCopiesPerV)
    {
      next.source[slot] = picks[k];
      ++copies[picks[k]];
    }

  // The first slot copying a V-particle keeps its heading; the later ones turn.
  next.turned.assign(n, false);
  std::vector<bool> used(n, false);
  for (int k = 0; k < n; ++k)
    if (next.source[k] >= 0)
    {
      next.turned[k] = used[next.source[k]];
      used[next.source[k]] = true;
    }
  return next;
}
}  // namespace amcr
