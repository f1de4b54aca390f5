// Radial-AMCR (paper 3.6): the API that the nodelet and the offline runner share.
//
//   amcr::Params params = amcr::loadParams("config/amcr.yaml");  // amcr/io/params_file.h
//   auto memory = std::make_shared<amcr::PrototypeMemory>(
//       amcr::PrototypeMemory::loadDirectory("prototypes/", params));
//   amcr::Recognizer recognizer(params, memory);
//   for (const cv::Mat& frame : frames)
//     amcr::RecognitionResult result = recognizer.step(frame);
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/extraction/flow_tracker.h"
#include "amcr/extraction/recognition_result.h"
#include "amcr/extraction/rival_cache.h"
#include "amcr/filter/exploration_policy.h"
#include "amcr/filter/filter_memory.h"
#include "amcr/filter/filter_view.h"
#include "amcr/filter/particle_filter.h"
#include "amcr/filter/particles.h"
#include "amcr/frame_budget.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/working_scale.h"

namespace amcr
{
/// One step per frame, in phases that talk through explicit values: the
/// flow tracker says where the V-particles go (flow_tracker.h), the particle
/// filter runs paper 3.6 on them (particle_filter.h), the result extraction
/// reads the filter and returns the objects and its feedback
/// (object_extractor.h), which the filter takes at once.
class Recognizer
{
public:
  /// Validates `params` (ParameterError) and takes a memory that must not be
  /// empty (MemoryError). The random generator is seeded with params.seed.
  Recognizer(const Params& params, std::shared_ptr<const PrototypeMemory> memory);
  /// The same with the memory made ready beforehand (filter_memory.h), for
  /// its parameters: only the swap remains to do here.
  explicit Recognizer(FilterMemory memory);

  /// Replaces the exploration policy (the default reflects at edges).
  void setPolicy(std::unique_ptr<ExplorationPolicy> policy);

  /// Replaces the clock of the frame budget (default: steadyClock()); it
  /// also times result.time_ms.
  void setClock(Clock clock);

  /// Swaps the memory and resets the filter.
  void setMemory(std::shared_ptr<const PrototypeMemory> memory);
  /// The same with a memory made ready beforehand for this recognizer's
  /// parameters (ParameterError otherwise): a swap, no build, so a caller
  /// can build it on another thread while this one recognizes. Returns the
  /// memory it replaced, to be freed where that costs nobody.
  FilterMemory setMemory(FilterMemory memory);

  /// Swaps in a memory that extends the current one (a prototype taught at
  /// runtime, ParticleFilter::extendMemory) without a reset: particles,
  /// tracks and the optical flow go on. MemoryError otherwise (nothing changes).
  void extendMemory(std::shared_ptr<const PrototypeMemory> memory);
  /// The same with a memory made ready beforehand, as setMemory(FilterMemory).
  FilterMemory extendMemory(FilterMemory memory);

  /// Forgets everything: particles are re-seeded at the next step, the
  /// generator is re-seeded with params.seed, the optical flow restarts, the
  /// frame budget's time estimates start again from 0 (the policy and the
  /// clock stay).
  /// Track ids go on counting: none is reused in the recognizer's life.
  void reset();

  /// Processes the next frame (any type prepareScanImage takes; InputError
  /// otherwise): the V-particles ride the optical flow from the previous
  /// frame (params.optical_flow), then one iteration of paper 3.6 runs, or,
  /// under params.frame_budget_ms, as much of it as fits (the rest follows
  /// in the next frames). A change of image size re-seeds the V-particles.
  /// An input larger than params.working_resolution is reduced to it first
  /// (working_scale.h); the result is in input px all the same.
  RecognitionResult step(const cv::Mat& image);

  /// Moves every V-particle by an external displacement (optical flow) without
  /// changing its correspondence: its M-particles stay where they are.
  /// `displacement` has one entry per V-particle (InputError otherwise), in
  /// input px of the last step's image.
  void moveVParticles(const std::vector<cv::Point2f>& displacement);

  // State, for overlays and diagnostics.
  const Params& params() const { return params_; }
  const PrototypeMemory& memory() const { return filter_.memory(); }
  /// The V-particles as the filter keeps them: in working px (view() gives input px).
  const std::vector<VParticle>& vParticles() const { return filter_.vParticles(); }
  /// The map between the last step's input and the image the filter worked on.
  const WorkingScale& workingScale() const { return scale_; }
  const MParticleSet& mParticles() const { return filter_.mParticles(); }
  int mParticlesPerV() const { return filter_.mParticlesPerV(); }
  /// The filter itself (M-particle ranges, the proposal index and what its
  /// build left out).
  const ParticleFilter& filter() const { return filter_; }
  /// The prototype of each of a V-particle's M-particle slots at seeding:
  /// the context prior (params.prototype_priors) as particle counts.
  const std::vector<int>& priorSlots() const { return filter_.priorSlots(); }
  long iteration() const { return iteration_; }
  /// Every object the last step's extraction fitted and verified on the
  /// image, reported or not, best score first, in input px: why a shape in
  /// view was not reported (a miss at the threshold, at the support, or no
  /// candidate at all).
  const std::vector<RecognizedObject>& verifiedCandidates() const { return verified_; }
  /// The filter as the overlay draws it: each V-particle with its dominant
  /// prototype (as the result extraction defines it) and its flow trail, and
  /// the M-particles per prototype.
  FilterView view() const;

private:
  /// The V-particle updates of this frame: a whole round, or under the frame
  /// budget as many as fit (at least one, never past the end of a round).
  /// Returns the share of an iteration run; `round_done` tells whether the
  /// round ended.
  double runUpdates(const RadialScanner& scanner, double frame_start, bool& round_done);
  std::vector<RayPlace> coverageOfFrame(cv::Size working_size, double min_object_size);
  /// Moves the V-particles by the optical flow; returns how many were lost.
  int followFlow(const RadialScanner& scanner);

  Params params_;
  ParticleFilter filter_;
  FlowTracker tracker_;
  FrameBudget budget_;
  long iteration_ = 0;
  int next_v_ = 0;  // the V-particle the current round goes on with (frame budget)
  std::int64_t coverage_frame_ = 0;  // frames since the coverage lattice started over (coverage_schedule.h)
  RivalCache rivals_;  // the generic rivals of the memory's prototypes, fitted as fits need them
  std::vector<FlowTrail> trails_;  // per V-particle, of the last step's flow (empty: none), working px
  WorkingScale scale_;             // of the last step (empty sizes before the first)
  std::vector<RecognizedObject> verified_;  // of the last step, input px
};
}  // namespace amcr
