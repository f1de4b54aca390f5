// The particle filter: set-up, one V-particle's iteration, the evidence and
// the moves from outside (optical flow). Where new particles start is in
// particle_filter_seeding.cpp, the mixture proposal from the index in
// particle_filter_proposals.cpp, what the held objects change in
// particle_filter_held_objects.cpp, the measurement in
// particle_filter_measurement.cpp, the resampling in
// particle_filter_resampling.cpp.
#include "amcr/filter/particle_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
ParticleFilter::ParticleFilter(const Params& params, std::shared_ptr<const PrototypeMemory> memory)
  : ParticleFilter(FilterMemory(params, std::move(memory)))
{
}

ParticleFilter::ParticleFilter(FilterMemory memory)
  : params_(memory.params_)
  , memory_(std::move(memory.memory_))
  , prior_(std::move(memory.prior_))
  , policy_(std::make_unique<ReflectAtEdgesPolicy>(params_.v_step, params_.reflection_jitter))
  , discriminator_(params_.v_step, params_.discriminative_min_gain)
  , observation_(params_)
  , motion_(params_)
  , rng_(params_.seed)
  , index_(std::move(memory.index_))
  , profile_index_(std::move(memory.profile_index_))
  , places_(std::move(memory.places_))
  , index_warnings_(std::move(memory.warnings_))
{
  reset();
}

void ParticleFilter::setPolicy(std::unique_ptr<ExplorationPolicy> policy)
{
  if (!policy)
    throw ParameterError("the exploration policy must not be null");
  policy_ = std::move(policy);
}

void ParticleFilter::setMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  setMemory(FilterMemory(params_, std::move(memory)));
}

FilterMemory ParticleFilter::setMemory(FilterMemory memory)
{
  swapMemory(memory);
  reset();
  return memory;
}

void ParticleFilter::extendMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  if (!memory || !memory_->isPrefixOf(*memory))  // checked before the build
    throw MemoryError("the new memory does not extend the current one (its first " +
                      std::to_string(memory_->size()) + " prototypes must be the current ones)");
  extendMemory(FilterMemory(params_, std::move(memory)));
}

FilterMemory ParticleFilter::extendMemory(FilterMemory memory)
{
  if (!memory_->isPrefixOf(*memory.memory_))
    throw MemoryError("the new memory does not extend the current one (its first " +
                      std::to_string(memory_->size()) + " prototypes must be the current ones)");
  swapMemory(memory);
  return memory;
}

void ParticleFilter::swapMemory(FilterMemory& memory)
{
  if (!sameParameters(memory.params_, params_))
    throw ParameterError("the memory was made ready for other parameters than the filter's");
  std::swap(memory_, memory.memory_);
  std::swap(prior_, memory.prior_);
  std::swap(index_, memory.index_);
  std::swap(profile_index_, memory.profile_index_);
  std::swap(places_, memory.places_);
  std::swap(index_warnings_, memory.warnings_);
}

void ParticleFilter::reset()
{
  rng_ = Rng(params_.seed);
  work_.clear();
  for (Rng& stream : Rng::streams(params_.seed, static_cast<std::size_t>(params_.num_v_particles)))
    work_.emplace_back(stream);
  v_.clear();
  m_count_.clear();
  m_ = MParticleSet();
  m_scratch_ = MParticleSet();
  leading_.clear();
  image_size_ = cv::Size();
  held_mask_.release();
  held_v_.clear();
  held_prototypes_.clear();
}

// ---------------------------------------------------------------------------
// One V-particle's iteration

void ParticleFilter::update(int v_index, const RadialScanner& scanner)
{
  VParticle& v = v_[v_index];
  const MRange r = mRange(v_index);

  // Control: to where competing clusters disagree (paper 4.3's feedback
  // control, discriminative_attention.h), else from the policy; the
  // M-particles follow through their A (paper 4.2).
  Rng& rng = work_[v_index].rng;
  const double heading_before = v.theta;
  Control u;
  v.competing = CompetingHypotheses();
  v.discriminating = false;
  if (params_.discriminative_moves || params_.competing_fits > 0)
  {
    const CompetingHypotheses competing =
        competingHypotheses(m_, r, v.x, v.y, static_cast<float>(params_.cluster_radius),
                            static_cast<float>(params_.discriminative_min_share));
    if (decidingBetweenLookAlikes(competing, static_cast<float>(params_.cluster_min_share)))
      v.competing = competing;
    DiscriminativeMove move;
    if (params_.discriminative_moves &&
        discriminator_.choose(v, v.competing, *memory_, observation_, image_size_, places_.get(), move))
    {
      u = move.control;
      v.discriminating = true;
    }
  }
  if (!v.discriminating)
    u = policy_->decide(v, scanner, rng);
  MotionModel::moveV(v, u);
  v.theta = static_cast<float>(wrapAngle(v.theta));
  motion_.moveM(m_, r.begin, r.end, heading_before, u, rng);
  ++v.age;

  measure(v_index, scanner);
  accumulateEvidence(v_index);
  resampleM(v_index);
}

// The V-particles are independent within an iteration (paper 3.6): each
// writes only its own particles and scratch, and draws from its own stream.
void ParticleFilter::updateRange(int first, int last, const RadialScanner& scanner)
{
  parallelFor(last - first, resolveThreads(params_.num_threads), [&](int k) { update(first + k, scanner); });
}

// Evidence that v lies on an interpretable shape: the log of its
// M-particles' mean importance weight, the likelihood times the proposal's
// weight (spec "Resampling V").
void ParticleFilter::accumulateEvidence(int v_index)
{
  const MRange r = mRange(v_index);
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = r.begin; i < r.end; ++i)
    top = std::max(top, static_cast<double>(m_.log_likelihood[i] + m_.log_proposal[i]));
  double sum = 0.0;
  for (std::size_t i = r.begin; i < r.end; ++i)
    sum += std::exp(m_.log_likelihood[i] + m_.log_proposal[i] - top);
  VParticle& v = v_[v_index];
  v.log_evidence_sum += top + std::log(sum / r.size());
  ++v.evidence_count;
}

void ParticleFilter::addEvidence(const std::vector<EvidenceBonus>& evidence)
{
  for (const EvidenceBonus& bonus : evidence)
    v_[bonus.v].log_evidence_sum += bonus.log_weight;
}

void ParticleFilter::setLeading(std::vector<LeadingHypothesis> leading) { leading_ = std::move(leading); }

MRange ParticleFilter::mRange(int v) const
{
  MRange r;
  r.begin = static_cast<std::size_t>(v) * mParticlesPerV();
  r.end = r.begin + static_cast<std::size_t>(m_count_[v]);
  return r;
}

std::vector<MRange> ParticleFilter::mRanges() const
{
  std::vector<MRange> ranges(v_.size());
  for (std::size_t i = 0; i < v_.size(); ++i)
    ranges[i] = mRange(static_cast<int>(i));
  return ranges;
}

double ParticleFilter::meanMParticles() const
{
  if (m_count_.empty())
    return 0.0;
  double sum = 0.0;
  for (int count : m_count_)
    sum += count;
  return sum / m_count_.size();
}

// ---------------------------------------------------------------------------
// Moves from outside

int ParticleFilter::applyFlow(const std::vector<VParticleMove>& moves, const RadialScanner& scanner)
{
  const std::size_t per_v = static_cast<std::size_t>(mParticlesPerV());
  std::vector<int> lost;
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    VParticle& v = v_[i];
    const VParticleMove& move = moves[i];
    switch (move.kind)
    {
      case VParticleMove::Kind::kWithTrack:
        v.x = move.x;
        v.y = move.y;
        v.theta = move.theta;
        break;
      case VParticleMove::Kind::kWithFlow:
        v.x = move.x;
        v.y = move.y;
        break;
      case VParticleMove::Kind::kLost:
        lost.push_back(static_cast<int>(i));
        break;
    }
  }
  parallelFor(static_cast<int>(lost.size()), resolveThreads(params_.num_threads), [&](int k) {
    const std::size_t i = static_cast<std::size_t>(lost[k]);
    seedVAndM(v_[i], m_, i * per_v, (i + 1) * per_v, scanner, work_[i]);
    m_count_[i] = static_cast<int>(per_v);
  });
  return static_cast<int>(lost.size());
}

void ParticleFilter::displace(const std::vector<cv::Point2f>& displacement)
{
  if (displacement.size() != v_.size())
    throw InputError("moveVParticles: got " + std::to_string(displacement.size()) + " displacements for " +
                     std::to_string(v_.size()) + " V-particles");
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    if (!std::isfinite(displacement[i].x) || !std::isfinite(displacement[i].y))
      throw InputError("moveVParticles: displacement " + std::to_string(i) + " is not finite");
  }
  const float max_x = static_cast<float>(std::max(0, image_size_.width - 1));
  const float max_y = static_cast<float>(std::max(0, image_size_.height - 1));
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    v_[i].x = std::min(std::max(v_[i].x + displacement[i].x, 0.f), max_x);
    v_[i].y = std::min(std::max(v_[i].y + displacement[i].y, 0.f), max_y);
  }
}
}  // namespace amcr
