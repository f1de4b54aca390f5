#include "amcr/recognizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "amcr/errors.h"
#include "amcr/heading_proposal.h"
#include "amcr/ray_directions.h"
#include "amcr/relational_update.h"
#include "amcr/resampling.h"

namespace amcr
{
namespace
{
constexpr int kMaxCopiesPerV = 3;         // copies one V-particle may get at a V-resampling
constexpr int kVParticlesPerObject = 12;  // V-particles a recognized object keeps at full V-weight
constexpr double kEstimateDecay = 0.9;    // per frame, of the frame budget's running cost estimates
constexpr float kMinSeedRayLength = 4.f;  // px: shorter rays at a seed place mean texture, not a region
}  // namespace

Recognizer::Recognizer(const Params& params, std::shared_ptr<const PrototypeMemory> memory)
  : params_((params.validate(), params))
  , policy_(std::make_unique<ReflectAtEdgesPolicy>(params.v_step, params.reflection_jitter))
  , observation_(params)
  , motion_(params)
  , rng_(params.seed)
  , flow_(params.flow_window, params.flow_levels, params.flow_max_error)
{
  setMemory(std::move(memory));
}

void Recognizer::setPolicy(std::unique_ptr<ExplorationPolicy> policy)
{
  if (!policy)
    throw ParameterError("the exploration policy must not be null");
  policy_ = std::move(policy);
}

void Recognizer::setMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  if (!memory || memory->empty())
    throw MemoryError("the recognizer needs a prototype memory with at least one prototype");
  memory_ = std::move(memory);
  buildPriorSlots();
  reset();
}

void Recognizer::buildPriorSlots()
{
  const std::size_t count = memory_->size();
  std::vector<double> weight(count, 1.0);
  for (const auto& prior : params_.prototype_priors)
  {
    bool found = false;
    for (std::size_t p = 0; p < count; ++p)
      if ((*memory_)[p].label() == prior.first)
      {
        weight[p] = prior.second;
        found = true;
      }
    if (!found)
      throw ParameterError("prototype_priors names '" + prior.first + "', which is not a label of the memory");
  }
  active_.clear();
  double total = 0.0;
  for (std::size_t p = 0; p < count; ++p)
    if (weight[p] > 0.0)
    {
      active_.push_back(static_cast<int>(p));
      total += weight[p];
    }
  if (active_.empty())
    throw ParameterError("prototype_priors gives every prototype of the memory weight 0");

  // m_particles_per_prototype per active prototype, shared in proportion to
  // the weights (largest remainder, so the shares add up exactly).
  const int slots = params_.m_particles_per_prototype * static_cast<int>(active_.size());
  std::vector<int> share(active_.size());
  std::vector<std::pair<double, int>> remainder;
  int given = 0;
  for (std::size_t a = 0; a < active_.size(); ++a)
  {
    const double exact = slots * weight[active_[a]] / total;
    share[a] = static_cast<int>(std::floor(exact));
    given += share[a];
    remainder.emplace_back(exact - share[a], static_cast<int>(a));
  }
  std::stable_sort(remainder.begin(), remainder.end(), [](const auto& l, const auto& r) { return l.first > r.first; });
  for (int k = 0; given < slots; ++k, ++given)
    ++share[remainder[k % remainder.size()].second];
  slot_prototype_.clear();
  for (std::size_t a = 0; a < active_.size(); ++a)
    slot_prototype_.insert(slot_prototype_.end(), share[a], active_[a]);

  prior_cdf_.clear();
  const bool uniform = std::all_of(active_.begin(), active_.end(), [&](int p) { return weight[p] == weight[active_[0]]; });
  if (!uniform)
  {
    double sum = 0.0;
    for (int p : active_)
      prior_cdf_.push_back(sum += weight[p] / total);
  }
}

int Recognizer::drawPrototype()
{
  if (prior_cdf_.empty())
    return active_[rng_.index(active_.size())];
  const double u = rng_.uniform();
  const auto it = std::upper_bound(prior_cdf_.begin(), prior_cdf_.end(), u);
  return active_[std::min<std::size_t>(it - prior_cdf_.begin(), active_.size() - 1)];
}

void Recognizer::reset()
{
  rng_ = Rng(params_.seed);
  v_.clear();
  m_ = MParticleSet();
  m_scratch_ = MParticleSet();
  clusters_.clear();
  leading_.clear();
  tracks_.clear();
  flow_.reset();
  flow_origins_.clear();
  image_size_ = cv::Size();
  iteration_ = 0;
  next_v_ = 0;
}

RecognitionResult Recognizer::step(const cv::Mat& image)
{
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); };
  const auto start = Clock::now();
  const cv::Mat grey = toGray8(image);  // throws InputError before any state changes
  scan_image_ = prepareScanImage(grey, params_.blur_sigma);
  const RadialScanner scanner(scan_image_, params_.edge_threshold, params_.max_ray_length);
  RecognitionResult result;
  const bool fresh = v_.empty() || scan_image_.size() != image_size_;
  if (fresh)
    seedAll(scanner);
  flow_origins_.clear();
  if (params_.optical_flow)
  {
    flow_.push(grey);
    if (!fresh && flow_.ready())
      result.flow_failures = followFlow(scanner);
  }

  // Paper 3.6: move every V-particle, predict and weight its M-particles,
  // resample them. Under a frame budget a round over the V-particles spans
  // frames (the paper splits an iteration over two); a step never goes past
  // the end of a round, and updates at least one V-particle.
  const int n = static_cast<int>(v_.size());
  const double budget = params_.frame_budget_ms;
  int updated = 0;
  bool round_done = false;
  const auto updates_start = Clock::now();
  while (!round_done)
  {
    if (budget > 0.0 && updated > 0 && since(start) + v_update_ms_ + extraction_ms_ > budget)
      break;
    updateV(next_v_, scanner);
    ++updated;
    if (++next_v_ == n)
    {
      next_v_ = 0;
      ++iteration_;
      round_done = true;
    }
  }
  // The estimates fall slowly and rise at once: a frame that ran over the
  // budget makes the next frames careful.
  if (budget > 0.0)
    v_update_ms_ = std::max(kEstimateDecay * v_update_ms_, since(updates_start) / updated);
  result.iterations = static_cast<double>(updated) / n;

  const auto extraction_start = Clock::now();
  result.objects = extractObjects(scanner);
  for (const auto& c : clusters_)
    result.converged_v_particles += c.share >= params_.cluster_min_share ? 1 : 0;
  if (round_done && iteration_ % params_.v_resample_interval == 0)
    resampleV(scanner, result.objects);
  tracks_.assign(result.objects);
  if (budget > 0.0)
    extraction_ms_ = std::max(kEstimateDecay * extraction_ms_, since(extraction_start));

  result.iteration = iteration_;
  result.time_ms = since(start);
  return result;
}

void Recognizer::moveVParticles(const std::vector<cv::Point2f>& displacement)
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

// ---------------------------------------------------------------------------
// Seeding

void Recognizer::seedAll(const RadialScanner& scanner)
{
  image_size_ = scanner.image().size();
  per_v_ = static_cast<int>(slot_prototype_.size());
  v_.assign(params_.num_v_particles, VParticle());
  m_.resize(v_.size() * per_v_);
  m_scratch_.resize(m_.size());
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    seedV(v_[i], scanner);
    seedMRange(m_, i * per_v_, (i + 1) * per_v_, v_[i].rays);
  }
  clusters_.clear();
  leading_.clear();
  tracks_.clear();
  next_v_ = 0;
}

// Spec "Where V-particles start matters": prefer places enclosed by edges
// (inside closed regions), trying `seed_attempts` random places.
void Recognizer::seedV(VParticle& v, const RadialScanner& scanner)
{
  int best_enclosure = -1;
  for (int attempt = 0; attempt < params_.seed_attempts; ++attempt)
  {
    const float x = static_cast<float>(rng_.uniform(1.0, std::max(1.0, image_size_.width - 2.0)));
    const float y = static_cast<float>(rng_.uniform(1.0, std::max(1.0, image_size_.height - 2.0)));
    const float theta = static_cast<float>(rng_.uniform(-M_PI, M_PI));
    // Rays that meet an edge, but not at once: texture is not a region.
    int enclosure = 0;
    RaySignature rays;
    for (int k = 0; k < kFeatureRays; ++k)
    {
      const RayHit hit = scanner.scanAngle(x, y, theta + k * kFeatureBinStep * kBinAngle);
      enclosure += (hit.valid && hit.distance >= kMinSeedRayLength) ? 1 : 0;
      rays.distance[k] = hit.valid ? std::max(hit.distance, 1e-3f) : 0.f;
    }
    if (enclosure > best_enclosure)
    {
      best_enclosure = enclosure;
      v = VParticle();
      v.x = x;
      v.y = y;
      v.theta = theta;
      v.rays = rays;
    }
    if (enclosure >= params_.seed_enclosure_rays)
      break;
  }
}

void Recognizer::seedMRange(MParticleSet& set, std::size_t begin, std::size_t end, const RaySignature& rays)
{
  for (std::size_t j = 0; j < end - begin; ++j)
    seedM(set, begin + j, slot_prototype_[j], rays);
}

// A uniform position inside the prototype; the heading from the proposal
// (heading_proposal.h) when the V-particle sees enough edges, else uniform.
void Recognizer::seedM(MParticleSet& set, std::size_t index, int prototype, const RaySignature& rays)
{
  const Prototype& p = (*memory_)[prototype];
  const cv::Point& at = p.interior()[rng_.index(p.interior().size())];
  set.x[index] = static_cast<float>(at.x);
  set.y[index] = static_cast<float>(at.y);
  const int bin = bestHeadingBin(p, at.x, at.y, rays);
  const double heading = bin >= 0 ? binToAngle(bin) : rng_.uniform(-M_PI, M_PI);
  set.theta[index] = static_cast<float>(wrapAngle(heading));
  set.prototype[index] = prototype;
  for (auto& a : set.affine)
    a[index] = 0.f;
  set.affine_valid[index] = 0;
  set.log_likelihood[index] = static_cast<float>(kFeatureRays * observation_.logInvalid());
}

// ---------------------------------------------------------------------------
// One V-particle's iteration

void Recognizer::updateV(int v_index, const RadialScanner& scanner)
{
  VParticle& v = v_[v_index];
  const std::size_t begin = static_cast<std::size_t>(v_index) * per_v_, end = begin + per_v_;

  // Control from the policy; the M-particles follow through their A (paper 4.2).
  const double heading_before = v.theta;
  const Control u = policy_->decide(v, scanner, rng_);
  MotionModel::moveV(v, u);
  v.theta = static_cast<float>(wrapAngle(v.theta));
  motion_.moveM(m_, begin, end, heading_before, u, rng_);
  ++v.age;

  // The V-particle's measurement: 8 feature rays (k * 45 deg) and the two
  // further triangle rays (120, 240 deg); ray 0 serves both.
  float v_dist[kFeatureRays + 2];
  bool v_valid[kFeatureRays + 2];
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const RayHit hit = scanner.scanAngle(v.x, v.y, v.theta + k * kFeatureBinStep * kBinAngle);
    v_dist[k] = hit.distance;
    v_valid[k] = hit.valid;
    v.rays.distance[k] = hit.valid ? std::max(hit.distance, 1e-3f) : 0.f;
  }
  for (int t = 1; t < kTriangleRays; ++t)
  {
    const RayHit hit = scanner.scanAngle(v.x, v.y, v.theta + t * kTriangleBinStep * kBinAngle);
    v_dist[kFeatureRays + t - 1] = hit.distance;
    v_valid[kFeatureRays + t - 1] = hit.valid;
  }
  measureM(v_index, v_dist, v_valid);

  // Evidence that v lies on an interpretable shape: the log of its
  // M-particles' mean likelihood (spec "Resampling V").
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = begin; i < end; ++i)
    top = std::max(top, static_cast<double>(m_.log_likelihood[i]));
  double sum = 0.0;
  for (std::size_t i = begin; i < end; ++i)
    sum += std::exp(m_.log_likelihood[i] - top);
  v.log_evidence_sum += top + std::log(sum / per_v_);
  ++v.evidence_count;

  resampleM(v_index);
}

// The update of every relational particle (v, m): the triangle affine of
// paper 4.1 and the likelihood of eqs. 5-6 (ObservationModel::measure).
void Recognizer::measureM(int v_index, const float* v_dist, const bool* v_valid)
{
  const VParticle& v = v_[v_index];
  const std::size_t begin = static_cast<std::size_t>(v_index) * per_v_, end = begin + per_v_;
  // Spec "Motion model": an M-particle that leaves its prototype is re-seeded,
  // in index order (the update itself draws nothing).
  for (std::size_t i = begin; i < end; ++i)
    if (!insideTable((*memory_)[m_.prototype[i]], nearestTablePixel(m_.x[i], m_.y[i])))
      seedM(m_, i, m_.prototype[i], v.rays);
  observation_.measure(*memory_, rayEnds(v, v_dist, v_valid), m_, begin, end);
}

// SIR over all prototypes of R^-1(v) (paper 3.6), with a share re-seeded
// uniformly and a share placed at the poses the leading hypotheses imply.
void Recognizer::resampleM(int v_index)
{
  const VParticle& v = v_[v_index];
  const std::size_t begin = static_cast<std::size_t>(v_index) * per_v_;
  weight_scratch_.resize(per_v_);
  float worst = std::numeric_limits<float>::infinity();
  for (int j = 0; j < per_v_; ++j)
  {
    weight_scratch_[j] = m_.log_likelihood[begin + j];
    worst = std::min(worst, m_.log_likelihood[begin + j]);
  }
  int n_inject = leading_.empty() ? 0 : static_cast<int>(std::lround(params_.injection_fraction * per_v_));
  int n_reseed = static_cast<int>(std::lround(params_.m_reseed_fraction * per_v_));
  n_inject = std::min(n_inject, per_v_);
  n_reseed = std::min(n_reseed, per_v_ - n_inject);
  const int n_draw = per_v_ - n_inject - n_reseed;

  const std::vector<int> picks = systematicResampleLog(weight_scratch_, n_draw, rng_);
  int k = 0;
  for (; k < n_draw; ++k)
    m_scratch_.copyFrom(m_, begin + picks[k], begin + k);
  for (int j = 0; j < n_inject; ++j, ++k)
  {
    const LeadingHypothesis& h = leading_[j % leading_.size()];
    const Affine& a = h.image_to_table;
    const Prototype& p = (*memory_)[h.prototype];
    const cv::Point2d at = applyAffine(a, cv::Point2d(v.x, v.y));
    if (at.x < 0 || at.y < 0 || at.x > p.width() - 1 || at.y > p.height() - 1)
    {
      seedM(m_scratch_, begin + k, h.prototype, v.rays);
      continue;
    }
    const double hx = std::cos(v.theta), hy = std::sin(v.theta);
    m_scratch_.x[begin + k] = static_cast<float>(at.x + rng_.gaussian(params_.motion_noise_translation));
    m_scratch_.y[begin + k] = static_cast<float>(at.y + rng_.gaussian(params_.motion_noise_translation));
    m_scratch_.theta[begin + k] = static_cast<float>(std::atan2(a(1, 0) * hx + a(1, 1) * hy, a(0, 0) * hx + a(0, 1) * hy) +
                                                     rng_.gaussian(params_.motion_noise_rotation));
    m_scratch_.prototype[begin + k] = h.prototype;
    for (int e = 0; e < 6; ++e)
      m_scratch_.affine[e][begin + k] = static_cast<float>(a(e / 3, e % 3));
    m_scratch_.affine_valid[begin + k] = 1;
    m_scratch_.log_likelihood[begin + k] = worst;
  }
  for (int j = 0; j < n_reseed; ++j, ++k)
    seedM(m_scratch_, begin + k, drawPrototype(), v.rays);
  m_.copyRange(m_scratch_, begin, begin + per_v_);
}

// ---------------------------------------------------------------------------
// V-resampling (paper 3.6, every w iterations; attention feedback, paper 4.3)

void Recognizer::resampleV(const RadialScanner& scanner, const std::vector<RecognizedObject>& objects)
{
  const int n = static_cast<int>(v_.size());
  std::vector<double> log_weights(n);
  for (int i = 0; i < n; ++i)
    log_weights[i] = v_[i].evidence_count > 0 ? v_[i].log_evidence_sum / v_[i].evidence_count
                                              : -std::numeric_limits<double>::infinity();
  // Attention is shared between objects: the V-particles of an object
  // beyond kVParticlesPerObject share its weight, so that a recognized
  // object does not draw every V-particle away from the others and from
  // the unexplored rest of the image.
  for (const RecognizedObject& object : objects)
  {
    const double crowding = static_cast<double>(object.v_particles.size()) / kVParticlesPerObject;
    if (crowding > 1.0)
      for (int i : object.v_particles)
        log_weights[i] -= std::log(crowding);
  }
  const int n_reseed = std::min(n, static_cast<int>(std::lround(params_.v_reseed_fraction * n)));
  const int n_draw = n - n_reseed;
  const std::vector<int> picks = systematicResampleLog(log_weights, n_draw, rng_);

  // A V-particle gets at most kMaxCopiesPerV copies per resampling, so that
  // attention cannot collapse onto one region in a few rounds; the slots
  // left over are seeded afresh.
  std::vector<int> source(n, -1);
  std::vector<int> copies(n, 0);
  for (int k = 0; k < n_draw; ++k)
    if (copies[picks[k]] < kMaxCopiesPerV)
    {
      source[k] = picks[k];
      ++copies[picks[k]];
    }

  std::vector<VParticle> next(n);
  std::vector<bool> used(n, false);
  for (int k = 0; k < n; ++k)
  {
    const int from = source[k];
    if (from < 0)
    {
      seedV(next[k], scanner);
      seedMRange(m_scratch_, static_cast<std::size_t>(k) * per_v_, static_cast<std::size_t>(k + 1) * per_v_,
                 next[k].rays);
      continue;
    }
    next[k] = v_[from];
    for (int j = 0; j < per_v_; ++j)
      m_scratch_.copyFrom(m_, static_cast<std::size_t>(from) * per_v_ + j, static_cast<std::size_t>(k) * per_v_ + j);
    if (used[from])
    {
      // A copy turns to a random heading so the copies explore apart; its
      // M-particles turn with it through their A.
      const Control turn{rng_.uniform(-M_PI, M_PI), 0.0};
      motion_.moveM(m_scratch_, static_cast<std::size_t>(k) * per_v_, static_cast<std::size_t>(k + 1) * per_v_,
                    next[k].theta, turn, rng_);
      MotionModel::moveV(next[k], turn);
      next[k].theta = static_cast<float>(wrapAngle(next[k].theta));
    }
    used[from] = true;
  }
  for (auto& v : next)
  {
    v.log_evidence_sum = 0.0;
    v.evidence_count = 0;
  }
  v_ = std::move(next);
  std::swap(m_, m_scratch_);
  computeClusters();
}
}  // namespace amcr
