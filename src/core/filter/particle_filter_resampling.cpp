// Resampling of the particle filter (paper 3.6): the M-particles of one
// V-particle after its update, with the injection of the leading hypotheses,
// and the V-particles every w iterations, with the attention feedback of
// paper 4.3.
#include <algorithm>
#include <cmath>
#include <limits>

#include "amcr/base/parallel_for.h"
#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/particle_filter.h"
#include "amcr/filter/resampling.h"

namespace amcr
{
namespace
{
constexpr int kMaxCopiesPerV = 3;  // copies one V-particle may get at a V-resampling
// Share of the V-particles a reported object that is not held yet keeps at
// full V-weight: beyond it, the object's V-particles share that much weight.
constexpr double kObjectAttentionShare = 0.2;
}  // namespace

// SIR over all prototypes of R^-1(v) (paper 3.6), with a share re-seeded
// (seedM: uniformly or from the index) and a share placed at the poses the
// leading hypotheses imply; the weights are the likelihoods times the
// proposal weights of the M-particles seeded since the last resampling.
// KLD-sampling sets the size of the next generation.
void ParticleFilter::resampleM(int v_index)
{
  const VParticle& v = v_[v_index];
  VWorkspace& work = work_[v_index];
  std::vector<double>& weights = work.weights;
  const MRange r = mRange(v_index);
  const std::size_t begin = r.begin;
  const int count = static_cast<int>(r.size());
  weights.resize(count);
  float worst = std::numeric_limits<float>::infinity();
  for (int j = 0; j < count; ++j)
  {
    weights[j] = m_.log_likelihood[begin + j] + m_.log_proposal[begin + j];
    worst = std::min(worst, m_.log_likelihood[begin + j]);
  }
  const int capacity = mParticlesPerV();
  std::vector<int> picks;
  int next = capacity;
  if (params_.kld_error > 0.0)
  {
    picks = systematicResampleLog(weights, capacity, work.rng);
    next = kldCount(picks, begin, work.kld_bins);
  }
  // The re-seeded share is one of the budget: a V-particle whose particles
  // agree keeps exploring at the rate of a spread one (up to a quarter of
  // its particles).
  int n_inject = leading_.empty() ? 0 : static_cast<int>(std::lround(params_.injection_fraction * next));
  int n_reseed = std::min(static_cast<int>(std::lround(params_.m_reseed_fraction * capacity)),
                          next == capacity ? capacity : next / 4);
  n_inject = std::min(n_inject, next);
  n_reseed = std::min(n_reseed, next - n_inject);
  const int n_draw = next - n_inject - n_reseed;

  if (params_.kld_error > 0.0)
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
    m_scratch_.copyFrom(m_, begin + picks[k], begin + k);
    m_scratch_.log_proposal[begin + k] = 0.f;  // weighted once, at this resampling
  }
  for (int j = 0; j < n_inject; ++j, ++k)
    injectM(v, leading_[j % leading_.size()], begin + k, worst, work);
  for (int j = 0; j < n_reseed; ++j, ++k)
    seedM(m_scratch_, begin + k, scenePrototype(prior_.draw(work.rng), work.rng), v, work);
  m_.copyRange(m_scratch_, begin, begin + next);
  m_count_[v_index] = next;
}

namespace
{
// KLD-sampling's bins: about a cluster (cluster_radius 6 px) across, and
// the heading in 20 degree steps.
constexpr float kKldCell = 8.f;                                        // table px
constexpr float kKldAngle = static_cast<float>(20.0 * M_PI / 180.0);  // rad
}  // namespace

// Fox 2003, eq. for n_chi: the number of particles that keeps the KL
// divergence between them and the posterior below kld_error with
// probability 1 - delta (kld_z its upper quantile), for k occupied bins of
// (prototype, position, heading); amcl's pf_resample_limit is the same bound.
int ParticleFilter::kldCount(const std::vector<int>& picks, std::size_t begin,
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
    const std::uint64_t bx = cell(m_.x[i], kKldCell), by = cell(m_.y[i], kKldCell), bt = cell(m_.theta[i], kKldAngle);
    bins.push_back(static_cast<std::uint64_t>(m_.prototype[i]) << 48 | bx << 32 | by << 16 | bt);
  }
  std::sort(bins.begin(), bins.end());
  const int occupied = static_cast<int>(std::unique(bins.begin(), bins.end()) - bins.begin());
  const int capacity = mParticlesPerV();
  const int least = std::min(params_.min_m_particles_per_v, capacity);
  if (occupied <= 1)
    return least;
  const double k = occupied - 1;
  const double b = 2.0 / (9.0 * k);
  const double c = 1.0 - b + std::sqrt(b) * params_.kld_z;
  const double n = std::ceil(k / (2.0 * params_.kld_error) * c * c * c);
  return static_cast<int>(std::min<double>(capacity, std::max<double>(least, n)));
}

// The pose of v in the prototype that hypothesis h implies (its position,
// its heading mapped through h's affine), with motion noise; a pose outside
// the prototype is seeded instead.
void ParticleFilter::injectM(const VParticle& v, const LeadingHypothesis& h, std::size_t index, float worst,
                             VWorkspace& work)
{
  Rng& rng = work.rng;
  const Affine& a = h.image_to_table;
  const Prototype& p = (*memory_)[h.prototype];
  const cv::Point2d at = applyAffine(a, cv::Point2d(v.x, v.y));
  if (at.x < 0 || at.y < 0 || at.x > p.width() - 1 || at.y > p.height() - 1)
  {
    seedM(m_scratch_, index, h.prototype, v, work);
    return;
  }
  const double hx = std::cos(v.theta), hy = std::sin(v.theta);
  m_scratch_.x[index] = static_cast<float>(at.x + rng.gaussian(params_.motion_noise_translation));
  m_scratch_.y[index] = static_cast<float>(at.y + rng.gaussian(params_.motion_noise_translation));
  m_scratch_.theta[index] = static_cast<float>(std::atan2(a(1, 0) * hx + a(1, 1) * hy, a(0, 0) * hx + a(0, 1) * hy) +
                                               rng.gaussian(params_.motion_noise_rotation));
  m_scratch_.prototype[index] = h.prototype;
  for (int e = 0; e < 6; ++e)
    m_scratch_.affine[e][index] = static_cast<float>(a(e / 3, e % 3));
  m_scratch_.affine_valid[index] = kFittedAffine;
  float fitted[6];
  float shape[3] = {kFrontalShape[0], kFrontalShape[1], kFrontalShape[2]};
  for (int e = 0; e < 6; ++e)
    fitted[e] = m_scratch_.affine[e][index];
  viewShape(fitted, shape);  // leaves the frontal shape for a degenerate affine
  for (int k = 0; k < 3; ++k)
    m_scratch_.shape[k][index] = shape[k];
  m_scratch_.log_likelihood[index] = worst;
  m_scratch_.log_proposal[index] = 0.f;
}

// Each V-particle's log V-weight: its mean log evidence since the last
// V-resampling. Attention is shared between objects: the V-particles of a
// reported object beyond a share of them (kObjectAttentionShare) share its
// weight, so that an object does not draw every V-particle away from the
// others and from the unexplored rest of the image.
std::vector<double> ParticleFilter::attentionWeights(const std::vector<std::vector<int>>& object_v_particles) const
{
  const int n = static_cast<int>(v_.size());
  std::vector<double> log_weights(n);
  for (int i = 0; i < n; ++i)
    log_weights[i] = v_[i].evidence_count > 0 ? v_[i].log_evidence_sum / v_[i].evidence_count
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

std::vector<int> ParticleFilter::keepOnHeldObjects(std::vector<double>& log_weights) const
{
  std::vector<int> kept;
  const int held = static_cast<int>(held_v_.size());
  if (held == 0)
    return kept;
  // Each V-particle on at most one held object: the one it supports, else
  // the one whose hull holds it.
  std::vector<int> on(v_.size(), -1);
  for (int h = 0; h < held; ++h)
    for (int i : held_v_[h])
      if (i >= 0 && i < static_cast<int>(v_.size()))
        on[i] = h;
  std::vector<std::vector<int>> inside(held);
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    const int h = on[i] >= 0 ? on[i] : heldObjectAt(v_[i].x, v_[i].y);
    if (h >= 0)
      inside[h].push_back(static_cast<int>(i));
  }
  // Together the held objects keep at most half of the V-particles.
  const std::size_t keep = static_cast<std::size_t>(
      std::min(params_.held_v_particles, std::max(1, static_cast<int>(v_.size()) / (2 * held))));
  for (std::vector<int>& members : inside)
  {
    std::stable_sort(members.begin(), members.end(), [&](int a, int b) { return log_weights[a] > log_weights[b]; });
    for (std::size_t k = 0; k < members.size() && k < keep; ++k)
      kept.push_back(members[k]);
    for (int i : members)
      log_weights[i] = -std::numeric_limits<double>::infinity();
  }
  std::sort(kept.begin(), kept.end());
  return kept;
}

std::vector<int> ParticleFilter::resampleV(const RadialScanner& scanner,
                                           const std::vector<std::vector<int>>& object_v_particles)
{
  const int n = static_cast<int>(v_.size());
  const std::size_t per_v = static_cast<std::size_t>(mParticlesPerV());
  std::vector<double> log_weights = attentionWeights(object_v_particles);
  // A held object keeps a few V-particles; the rest, and the draws, go
  // where nothing is explained yet (inhibition of return, spec "Attention
  // that moves on").
  const std::vector<int> kept = keepOnHeldObjects(log_weights);
  const int n_free = n - static_cast<int>(kept.size());
  const bool any_weight = std::any_of(log_weights.begin(), log_weights.end(), [](double w) { return std::isfinite(w); });
  const int n_reseed = any_weight ? std::min(n_free, static_cast<int>(std::lround(params_.v_reseed_fraction * n_free)))
                                  : n_free;
  const int n_draw = n_free - n_reseed;
  const std::vector<int> picks = systematicResampleLog(log_weights, n_draw, rng_);

  // The kept V-particles first, then the draws: a V-particle gets at most
  // kMaxCopiesPerV copies per resampling, so that attention cannot collapse
  // onto one region in a few rounds; the slots left over are seeded afresh.
  std::vector<int> source(n, -1);
  std::vector<int> copies(n, 0);
  int slot = 0;
  for (int i : kept)
  {
    source[slot++] = i;
    ++copies[i];
  }
  for (int k = 0; k < n_draw; ++k, ++slot)
    if (copies[picks[k]] < kMaxCopiesPerV)
    {
      source[slot] = picks[k];
      ++copies[picks[k]];
    }

  // The first slot copying a V-particle keeps its heading; the later ones turn.
  std::vector<bool> turned(n, false);
  std::vector<bool> used(n, false);
  for (int k = 0; k < n; ++k)
    if (source[k] >= 0)
    {
      turned[k] = used[source[k]];
      used[source[k]] = true;
    }

  // Each slot is independent: it reads the old particles and writes its
  // own, with its own stream.
  std::vector<VParticle> next(n);
  std::vector<int> next_count(n, static_cast<int>(per_v));
  parallelFor(n, resolveThreads(params_.num_threads), [&](int k) {
    const int from = source[k];
    const std::size_t begin = static_cast<std::size_t>(k) * per_v, end = begin + per_v;
    if (from < 0)
    {
      seedVAndM(next[k], m_scratch_, begin, end, scanner, work_[k]);
      return;
    }
    next[k] = v_[from];
    next_count[k] = m_count_[from];
    for (std::size_t j = 0; j < static_cast<std::size_t>(m_count_[from]); ++j)
      m_scratch_.copyFrom(m_, static_cast<std::size_t>(from) * per_v + j, begin + j);
    const std::size_t copied_end = begin + static_cast<std::size_t>(next_count[k]);
    if (turned[k])
    {
      // A copy turns to a random heading so the copies explore apart; its
      // M-particles turn with it through their A.
      Rng& rng = work_[k].rng;
      const Control turn{rng.uniform(-M_PI, M_PI), 0.0};
      motion_.moveM(m_scratch_, begin, copied_end, next[k].theta, turn, rng);
      MotionModel::moveV(next[k], turn);
      next[k].theta = static_cast<float>(wrapAngle(next[k].theta));
    }
  });
  for (auto& v : next)
  {
    v.log_evidence_sum = 0.0;
    v.evidence_count = 0;
  }
  v_ = std::move(next);
  m_count_ = std::move(next_count);
  std::swap(m_, m_scratch_);
  return source;
}
}  // namespace amcr
