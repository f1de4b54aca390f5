// The particle filter: set-up, seeding, one V-particle's iteration, the
// evidence and the moves from outside (optical flow). The measurement is in
// particle_filter_measurement.cpp, the resampling in
// particle_filter_resampling.cpp.
#include "amcr/filter/particle_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/filter/corrected_scan.h"
#include "amcr/filter/heading_proposal.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr float kMinSeedRayLength = 4.f;  // px: shorter rays at a seed place mean texture, not a region
}  // namespace

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
// Seeding

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

namespace
{
constexpr int kFreePlaceDraws = 32;  // uniform draws before a free place is picked from the mask's free pixels
}  // namespace

// Inhibition of return (issue 15): what a held object shows is explained,
// so no V-particle starts there.
cv::Point2f ParticleFilter::drawFreePlace(Rng& rng) const
{
  const auto draw = [this, &rng] {
    // x before y, in two statements: the order of a call's arguments is unspecified.
    const float x = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size_.width - 2.0)));
    const float y = static_cast<float>(rng.uniform(1.0, std::max(1.0, image_size_.height - 2.0)));
    return cv::Point2f(x, y);
  };
  cv::Point2f place = draw();
  if (held_v_.empty())
    return place;
  for (int k = 1; k < kFreePlaceDraws && heldObjectAt(place.x, place.y) >= 0; ++k)
    place = draw();
  if (heldObjectAt(place.x, place.y) < 0)
    return place;
  // Held objects cover most of the image: a free pixel, if there is one.
  std::vector<cv::Point> free;
  cv::findNonZero(held_mask_ == 0, free);
  if (free.empty())
    return place;
  const cv::Point& at = free[rng.index(free.size())];
  return cv::Point2f(static_cast<float>(at.x), static_cast<float>(at.y));
}

void ParticleFilter::setHeldObjects(const std::vector<HeldObject>& held)
{
  for (std::size_t k = 0; k < held.size(); ++k)
    if (held[k].prototype < 0 || held[k].prototype >= static_cast<int>(memory_->size()))
      throw InputError("setHeldObjects: held object " + std::to_string(k) + " names prototype " +
                       std::to_string(held[k].prototype) + ", not in the memory of " +
                       std::to_string(memory_->size()) + " prototypes");
  held_mask_.release();
  held_v_.clear();
  held_prototypes_.clear();
  if (held.empty() || image_size_.empty())
    return;
  held_mask_ = cv::Mat::zeros(image_size_, CV_16UC1);
  for (const HeldObject& object : held)
  {
    held_v_.push_back(object.v_particles);
    if (prior_.probability(object.prototype) > 0.0)  // a prior of 0 keeps a prototype out
      held_prototypes_.push_back(object.prototype);
    if (object.outline.size() < 3)
      continue;
    // The hull: a V-particle in a concavity of the object sees the object.
    std::vector<cv::Point> points, hull;
    for (const cv::Point2d& p : object.outline)
      points.emplace_back(static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)));
    cv::convexHull(points, hull);
    cv::fillConvexPoly(held_mask_, hull, cv::Scalar(static_cast<double>(held_v_.size())));  // k + 1
  }
}

int ParticleFilter::heldObjectAt(float x, float y) const
{
  const int col = static_cast<int>(std::lround(x)), row = static_cast<int>(std::lround(y));
  if (held_v_.empty() || col < 0 || row < 0 || col >= held_mask_.cols || row >= held_mask_.rows)
    return -1;
  return static_cast<int>(held_mask_.at<std::uint16_t>(row, col)) - 1;
}

void ParticleFilter::seedMRange(MParticleSet& set, std::size_t begin, std::size_t end, const VParticle& v,
                                VWorkspace& work) const
{
  for (std::size_t j = 0; j < end - begin; ++j)
    seedM(set, begin + j, scenePrototype(prior_.slots()[j], work.rng), v, work);
}

// The scene's context (issue 15): what is held is likely to be in view
// again, as a copy, so the prior of new M-particles leans towards it.
int ParticleFilter::scenePrototype(int slot, Rng& rng) const
{
  if (held_prototypes_.empty() || params_.scene_prior_share <= 0.0 || rng.uniform() >= params_.scene_prior_share)
    return slot;
  return held_prototypes_[rng.index(held_prototypes_.size())];
}

double ParticleFilter::seedingProbability(int p) const
{
  if (held_prototypes_.empty() || params_.scene_prior_share <= 0.0)
    return prior_.probability(p);
  const double held = static_cast<double>(std::count(held_prototypes_.begin(), held_prototypes_.end(), p));
  return (1.0 - params_.scene_prior_share) * prior_.probability(p) +
         params_.scene_prior_share * held / static_cast<double>(held_prototypes_.size());
}

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

// A new M-particle has no affine yet, and the likelihood of all rays invalid.
void ParticleFilter::clearMeasurement(MParticleSet& set, std::size_t index) const
{
  for (auto& a : set.affine)
    a[index] = 0.f;
  set.affine_valid[index] = kNoAffine;
  set.log_likelihood[index] = static_cast<float>(kFeatureRays * observation_.logInvalid());
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
