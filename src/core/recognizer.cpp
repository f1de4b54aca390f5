// Radial-AMCR per frame: the phases in order, and the values they pass on.
#include "amcr/recognizer.h"

#include <algorithm>

#include "amcr/base/parallel_for.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/extraction/coverage_schedule.h"
#include "amcr/extraction/object_extractor.h"
#include "amcr/filter/discriminative_attention.h"
#include "amcr/scan/radial_scan.h"
#include "amcr/working_scale.h"

namespace amcr
{
namespace
{
/// The trails after a V-resampling: a copy keeps its source's trail (it
/// stands where its source stood), a V-particle seeded afresh has none.
std::vector<FlowTrail> inherit(const std::vector<FlowTrail>& trails, const std::vector<int>& ancestry)
{
  std::vector<FlowTrail> inherited;
  if (trails.empty())
    return inherited;
  for (int from : ancestry)
    inherited.push_back(from >= 0 ? trails[from] : FlowTrail());
  return inherited;
}

/// The held objects, each with the V-particles that support it
/// (`object_v_particles`, parallel to `objects`).
std::vector<HeldObject> heldObjects(const std::vector<RecognizedObject>& objects,
                                    const std::vector<std::vector<int>>& object_v_particles)
{
  std::vector<HeldObject> held;
  for (std::size_t i = 0; i < objects.size(); ++i)
    if (objects[i].state == ObjectState::kHeld)
      held.push_back({objects[i].prototype_id, objects[i].outline, object_v_particles[i]});
  return held;
}
}  // namespace

Recognizer::Recognizer(const Params& params, std::shared_ptr<const PrototypeMemory> memory)
  : params_((params.validate(), params))
  , filter_(params_, std::move(memory))
  , tracker_(params_, LifecycleRule(params_, params_))
  , budget_(params_.frame_budget_ms)
{
}

Recognizer::Recognizer(FilterMemory memory)
  : params_((memory.params().validate(), memory.params()))
  , filter_(std::move(memory))
  , tracker_(params_, LifecycleRule(params_, params_))
  , budget_(params_.frame_budget_ms)
{
}

void Recognizer::setPolicy(std::unique_ptr<ExplorationPolicy> policy) { filter_.setPolicy(std::move(policy)); }

void Recognizer::setClock(Clock clock) { budget_.setClock(std::move(clock)); }

void Recognizer::setMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  filter_.setMemory(std::move(memory));
  reset();
}

FilterMemory Recognizer::setMemory(FilterMemory memory)
{
  FilterMemory replaced = filter_.setMemory(std::move(memory));
  reset();
  return replaced;
}

void Recognizer::extendMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  filter_.extendMemory(std::move(memory));
  rivals_.clear();
}

FilterMemory Recognizer::extendMemory(FilterMemory memory)
{
  rivals_.clear();
  return filter_.extendMemory(std::move(memory));
}

void Recognizer::reset()
{
  filter_.reset();
  tracker_.reset();
  budget_.reset();
  trails_.clear();
  verified_.clear();
  iteration_ = 0;
  next_v_ = 0;
  coverage_frame_ = 0;
  rivals_.clear();  // the memory may have changed (setMemory)
}

RecognitionResult Recognizer::step(const cv::Mat& image)
{
  const double start = budget_.now();
  checkImageBound(image.cols, image.rows, "the input image");  // before any work on it
  const cv::Mat input_grey = toGray8(image);  // throws InputError before any state changes
  // The filter works on the working image (px parameters are its px) and
  // reports in input px: the same scene at any resolution meets the rays,
  // steps and seeding at the same size.
  const cv::Size previous_input = scale_.input;
  scale_ = chooseWorkingScale(input_grey.size(), params_.working_resolution);
  const cv::Mat grey = toWorkingImage(input_grey, scale_);
  const cv::Mat scan_image = prepareScanImage(grey, params_.blur_sigma);
  const RadialScanner scanner(scan_image, EdgeThresholds(scan_image, params_.edge_threshold, params_.edge_full_strength),
                              params_.max_ray_length);
  RecognitionResult result;
  double phase_start = budget_.now();
  result.times.prepare_ms = phase_start - start;

  // A new image size (or an empty filter) starts over; else the V-particles
  // ride the optical flow from the previous frame. Two inputs may share a
  // working size: the input's size decides too.
  const bool fresh = filter_.needsSeeding(scan_image.size()) || input_grey.size() != previous_input;
  if (fresh)
  {
    filter_.seed(scanner);
    tracker_.clearTracks();
    next_v_ = 0;
    coverage_frame_ = 0;
  }
  trails_.clear();
  if (params_.optical_flow)
  {
    tracker_.push(grey);
    if (!fresh && tracker_.ready())
      result.flow_failures = followFlow(scanner);
  }
  result.times.flow_ms = budget_.now() - phase_start;  // with the seeding of a fresh start

  // Paper 3.6: move every V-particle, predict and weight its M-particles,
  // resample them.
  bool round_done = false;
  phase_start = budget_.now();
  result.iterations = runUpdates(scanner, start, round_done);

  // The result extraction reads the filter; the filter takes its feedback.
  const double extraction_start = budget_.now();
  result.times.updates_ms = extraction_start - phase_start;
  // min_object_size is in input px (what a user measures in the image).
  ExtractionParams extraction_params = params_;
  extraction_params.min_object_size = params_.min_object_size * scale_.factor();
  ExtractionAids aids;
  aids.image_places = coverageOfFrame(scan_image.size(), extraction_params.min_object_size);
  aids.rivals = &rivals_;
  Extraction extraction = extractObjects(readFilter(filter_), scanner, tracker_.tracks(), extraction_params,
                                         params_, params_.num_threads, aids);
  filter_.addEvidence(extraction.feedback.evidence);
  filter_.setLeading(std::move(extraction.feedback.leading));
  for (const VParticleCluster& c : extraction.clusters)
    result.converged_v_particles += c.converged ? 1 : 0;
  // The life cycle (track_registry.h), then attention: what is held is
  // explained, and V-resampling looks elsewhere.
  result.objects = std::move(extraction.objects);
  result.objects_over_limit = extraction.over_limit;
  verified_ = std::move(extraction.verified);
  if (!params_.optical_flow)
    tracker_.holdStill();
  tracker_.assign(result.objects, scan_image.size(), result.lost);  // the tracks stay in working px, as the filter
  filter_.setHeldObjects(heldObjects(result.objects, extraction.feedback.object_v_particles));
  if (round_done && iteration_ % params_.v_resample_interval == 0)
    trails_ = inherit(trails_, filter_.resampleV(scanner, extraction.feedback.object_v_particles,
                                                 extraction.feedback.seed_places));
  if (!scale_.identity())
  {
    scaleResult(result, scale_.toInput());
    for (RecognizedObject& o : verified_)
      mapImageSide(o, scale_.toInput());
  }
  if (budget_.limited())
    budget_.recordExtraction(budget_.now() - extraction_start);

  result.mean_m_particles = filter_.meanMParticles();
  result.iteration = iteration_;
  const double end = budget_.now();
  result.times.extraction_ms = end - extraction_start;
  result.time_ms = end - start;
  return result;
}

// The frame's share of the coverage lattice (coverage_schedule.h), outside
// the tracked objects; none unless the pose votes and the lattice are on.
std::vector<RayPlace> Recognizer::coverageOfFrame(cv::Size working_size, double min_object_size)
{
  if (params_.pose_vote_fits <= 0 || params_.coverage_frames <= 0)
    return {};
  std::vector<std::vector<cv::Point2f>> held;
  for (const Track& t : tracker_.tracks().tracks())
    held.emplace_back(t.object.outline.begin(), t.object.outline.end());
  return coveragePlaces(working_size, coverageSpacing(min_object_size), params_.coverage_frames, coverage_frame_++,
                        held);
}

// Under a frame budget a round over the V-particles spans frames (the paper
// splits an iteration over two); a step never goes past the end of a round,
// and updates at least one V-particle. The V-particles are updated a batch
// at a time, a V-particle per thread (the whole round without a budget).
double Recognizer::runUpdates(const RadialScanner& scanner, double frame_start, bool& round_done)
{
  const int n = static_cast<int>(filter_.vParticles().size());
  const int batch = budget_.limited() ? resolveThreads(params_.num_threads) : n;
  int updated = 0;
  round_done = false;
  const double updates_start = budget_.now();
  while (!round_done)
  {
    if (budget_.limited() && updated > 0 && budget_.exhausted(budget_.now() - frame_start))
      break;
    const int last = std::min(n, next_v_ + batch);
    filter_.updateRange(next_v_, last, scanner);
    updated += last - next_v_;
    next_v_ = last;
    if (next_v_ == n)
    {
      next_v_ = 0;
      ++iteration_;
      round_done = true;
    }
  }
  if (budget_.limited())
    budget_.recordUpdates(budget_.now() - updates_start, updated);
  return static_cast<double>(updated) / n;
}

int Recognizer::followFlow(const RadialScanner& scanner)
{
  const std::vector<VParticle>& v = filter_.vParticles();
  const std::vector<VParticleMove> moves = tracker_.follow(v, filter_.imageSize());
  trails_.assign(v.size(), FlowTrail());
  for (std::size_t i = 0; i < v.size(); ++i)
    trails_[i] = {moves[i].kind != VParticleMove::Kind::kLost, cv::Point2f(v[i].x, v[i].y)};
  return filter_.applyFlow(moves, scanner);
}

FilterView Recognizer::view() const
{
  FilterView view;
  const Affine to_input = scale_.toInput();  // the overlay draws on the input
  const auto input = [&](const cv::Point2f& p) {
    return scale_.identity() ? p : cv::Point2f(applyAffine(to_input, cv::Point2d(p)));
  };
  const std::vector<VParticle>& v = filter_.vParticles();
  const std::vector<VParticleCluster> clusters = filterClusters(filter_);
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    VParticleView particle;
    particle.position = input(cv::Point2f(v[i].x, v[i].y));
    particle.theta = v[i].theta;
    if (clusters[i].converged)
      particle.dominant_prototype = clusters[i].prototype;
    if (i < trails_.size())
    {
      particle.trail = trails_[i];
      particle.trail.from = input(particle.trail.from);
    }
    particle.discriminating = v[i].discriminating;
    for (int k = 0; k < v[i].competing.count; ++k)
    {
      const CompetingHypothesis& h = v[i].competing.hypothesis[k];
      Affine table_to_image;
      if (hypothesisTableToImage(h, table_to_image))
        particle.competing.push_back({h.prototype, composeAffine(table_to_image, to_input), h.share});
    }
    view.v.push_back(particle);
  }
  const MParticleSet& m = filter_.mParticles();
  view.m_by_prototype.resize(filter_.memory().size());
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    const MRange r = filter_.mRange(static_cast<int>(k));
    for (std::size_t i = r.begin; i < r.end; ++i)
      view.m_by_prototype[m.prototype[i]].push_back({cv::Point2f(m.x[i], m.y[i]), static_cast<int>(k)});
  }
  return view;
}

void Recognizer::moveVParticles(const std::vector<cv::Point2f>& displacement)
{
  if (scale_.identity())
    return filter_.displace(displacement);
  // Input px -> working px: the linear part of the map only (a displacement).
  const Affine to_working = scale_.toWorking();
  std::vector<cv::Point2f> working = displacement;
  for (cv::Point2f& d : working)
    d = cv::Point2f(static_cast<float>(to_working(0, 0) * d.x), static_cast<float>(to_working(1, 1) * d.y));
  filter_.displace(working);
}
}  // namespace amcr
