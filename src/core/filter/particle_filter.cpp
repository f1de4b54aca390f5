// The particle filter: set-up, the memory swaps, one V-particle's iteration
// and the V-resampling in the order of paper 3.6, and the moves from outside
// (optical flow). What each step does is in its collaborator
// (particle_filter.h).
#include "amcr/filter/particle_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/filter/relational_update.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
ParticleFilter::ParticleFilter(const Params& params, std::shared_ptr<const PrototypeMemory> memory)
  : ParticleFilter(FilterMemory(params, std::move(memory)))
{
}

ParticleFilter::ParticleFilter(FilterMemory memory)
  : memory_(std::move(memory))
  , attention_(params(), params(), params())
  , observation_(params(), params())
  , motion_(params(), params())
  , seeder_(params(), params(), params(), observation_.logInvalid())
  , resampler_(params(), params(), params(), params().seed)
  , held_(params())
{
  reset();
}

void ParticleFilter::setMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  setMemory(FilterMemory(params(), std::move(memory)));
}

FilterMemory ParticleFilter::setMemory(FilterMemory memory)
{
  swapMemory(memory);
  reset();
  return memory;
}

namespace
{
MemoryError notAnExtension(const PrototypeMemory& current)
{
  return MemoryError("the new memory does not extend the current one (its first " + std::to_string(current.size()) +
                     " prototypes must be the current ones)");
}
}  // namespace

void ParticleFilter::extendMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  if (!memory || !this->memory().isPrefixOf(*memory))  // checked before the build
    throw notAnExtension(this->memory());
  extendMemory(FilterMemory(params(), std::move(memory)));
}

FilterMemory ParticleFilter::extendMemory(FilterMemory memory)
{
  if (!this->memory().isPrefixOf(*memory.memory()))
    throw notAnExtension(this->memory());
  swapMemory(memory);
  return memory;
}

void ParticleFilter::swapMemory(FilterMemory& memory)
{
  if (!sameParameters(memory.params(), params()))
    throw ParameterError("the memory was made ready for other parameters than the filter's");
  std::swap(memory_, memory);
}

void ParticleFilter::reset()
{
  const std::uint64_t seed = params().seed;
  resampler_.reset(seed);
  work_.clear();
  for (Rng& stream : Rng::streams(seed, static_cast<std::size_t>(params().num_v_particles)))
    work_.emplace_back(stream);
  v_.clear();
  m_count_.clear();
  m_ = MParticleSet();
  image_size_ = cv::Size();
  held_.clear();
}

void ParticleFilter::seed(const RadialScanner& scanner)
{
  if (scanner.image().size() != image_size_)
    held_.clear();  // outlines of another image size
  image_size_ = scanner.image().size();
  const std::size_t per_v = static_cast<std::size_t>(mParticlesPerV());
  v_.assign(params().num_v_particles, VParticle());
  m_count_.assign(v_.size(), static_cast<int>(per_v));
  m_.resize(v_.size() * per_v);
  resampler_.scratch().resize(m_.size());
  const SeedingScene scene = seedingScene();
  parallelFor(static_cast<int>(v_.size()), resolveThreads(params().num_threads), [&](int i) {
    seeder_.seedVAndM(v_[i], m_, i * per_v, (i + 1) * per_v, scanner, scene, work_[i]);
  });
  resampler_.clearLeading();
}

void ParticleFilter::setHeldObjects(const std::vector<HeldObject>& held)
{
  held_.set(held, image_size_, memory_.prior(), memory().size());
}

// ---------------------------------------------------------------------------
// One V-particle's iteration

void ParticleFilter::update(int v_index, const RadialScanner& scanner)
{
  VParticle& v = v_[v_index];
  const MRange r = mRange(v_index);
  // Control (paper 4.3), then the M-particles follow through their A (paper 4.2).
  Rng& rng = work_[v_index].rng;
  const double heading_before = v.theta;
  const Control u = attention_.decide(v, m_, r, memory_, observation_, image_size_, scanner, rng);
  MotionModel::moveV(v, u);
  v.theta = static_cast<float>(wrapAngle(v.theta));
  motion_.moveM(m_, r.begin, r.end, heading_before, u, rng);
  ++v.age;

  measure(v_index, scanner);
  accumulateEvidence(v_index);
  m_count_[v_index] = resampler_.resampleM(v, m_, r.begin, static_cast<int>(r.size()), mParticlesPerV(), seeder_,
                                           seedingScene(), work_[v_index]);
}

// The V-particles are independent within an iteration (paper 3.6): each
// writes only its own particles and scratch, and draws from its own stream.
void ParticleFilter::updateRange(int first, int last, const RadialScanner& scanner)
{
  parallelFor(last - first, resolveThreads(params().num_threads), [&](int k) { update(first + k, scanner); });
}

// The measurement of one V-particle: its ray scans, then the update of its
// relational particles (v, m) by the observation model (the triangle affine
// of paper 4.1 and the likelihood of eqs. 5-6, in relational_update.h).
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
  seeder_.findCandidates(v, scanner, memory_, work);  // for the M-particles this iteration seeds
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const RayHit hit = scanner.scanAngle(v.x, v.y, v.theta + t * kTriangleBinStep * kBinAngle);
    v_dist[kFeatureRays + t - 1] = hit.distance;
    v_valid[kFeatureRays + t - 1] = hit.valid;
  }

  // Spec "Motion model": an M-particle that has left its prototype is
  // re-seeded, in index order, before the update.
  const MRange r = mRange(v_index);
  const SeedingScene scene = seedingScene();
  for (std::size_t i = r.begin; i < r.end; ++i)
    if (!insideTable(memory()[m_.prototype[i]], nearestTablePixel(m_.x[i], m_.y[i])))
      seeder_.seedM(m_, i, m_.prototype[i], v, scene, work);
  // The relational update of paper 4.1 and eqs. 5-6 (ObservationModel::measure).
  observation_.measure(memory(), rayEnds(v, v_dist, v_valid), m_, r.begin, r.end);
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

// ---------------------------------------------------------------------------
// V-resampling: the Resampler draws the next generation, the filter copies it

std::vector<int> ParticleFilter::resampleV(const RadialScanner& scanner,
                                           const std::vector<std::vector<int>>& object_v_particles,
                                           const std::vector<RayPlace>& seed_places)
{
  const int n = static_cast<int>(v_.size());
  const std::size_t per_v = static_cast<std::size_t>(mParticlesPerV());
  const VGeneration generation = resampler_.drawV(v_, object_v_particles, held_);
  MParticleSet& next_m = resampler_.scratch();
  const SeedingScene scene = seedingScene();
  // Each slot is independent: it reads the old particles and writes its
  // own, with its own stream.
  std::vector<VParticle> next(n);
  std::vector<int> next_count(n, static_cast<int>(per_v));
  // The j-th slot seeded afresh starts at seed_places[j] while there are any.
  std::vector<int> place_of(n, -1);
  std::size_t places_given = 0;
  for (int k = 0; k < n && places_given < seed_places.size(); ++k)
    if (generation.source[k] < 0)
      place_of[k] = static_cast<int>(places_given++);
  parallelFor(n, resolveThreads(params().num_threads), [&](int k) {
    const int from = generation.source[k];
    const std::size_t begin = static_cast<std::size_t>(k) * per_v, end = begin + per_v;
    if (from < 0)
    {
      if (place_of[k] >= 0)
        seeder_.seedVAndMAt(seed_places[place_of[k]], next[k], next_m, begin, end, scanner, scene, work_[k]);
      else
        seeder_.seedVAndM(next[k], next_m, begin, end, scanner, scene, work_[k]);
      return;
    }
    next[k] = v_[from];
    next_count[k] = m_count_[from];
    for (std::size_t j = 0; j < static_cast<std::size_t>(m_count_[from]); ++j)
      next_m.copyFrom(m_, static_cast<std::size_t>(from) * per_v + j, begin + j);
    const std::size_t copied_end = begin + static_cast<std::size_t>(next_count[k]);
    if (generation.turned[k])
    {
      // A copy turns to a random heading so the copies explore apart; its
      // M-particles turn with it through their A.
      Rng& rng = work_[k].rng;
      const Control turn{rng.uniform(-M_PI, M_PI), 0.0};
      motion_.moveM(next_m, begin, copied_end, next[k].theta, turn, rng);
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
  std::swap(m_, next_m);
  return generation.source;
}

// ---------------------------------------------------------------------------
// The sets and moves from outside

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
  const SeedingScene scene = seedingScene();
  parallelFor(static_cast<int>(lost.size()), resolveThreads(params().num_threads), [&](int k) {
    const std::size_t i = static_cast<std::size_t>(lost[k]);
    seeder_.seedVAndM(v_[i], m_, i * per_v, (i + 1) * per_v, scanner, scene, work_[i]);
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
