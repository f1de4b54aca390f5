// Radial-AMCR (paper 3.6): the API that the nodelet and the offline runner share.
//
//   amcr::Params params = amcr::loadParams("config/amcr.yaml");
//   auto memory = std::make_shared<amcr::PrototypeMemory>(
//       amcr::PrototypeMemory::loadDirectory("prototypes/", params));
//   amcr::Recognizer recognizer(params, memory);
//   for (const cv::Mat& frame : frames)
//     amcr::RecognitionResult result = recognizer.step(frame);
#pragma once

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/exploration_policy.h"
#include "amcr/motion_model.h"
#include "amcr/object_extraction.h"
#include "amcr/observation_model.h"
#include "amcr/optical_flow.h"
#include "amcr/params.h"
#include "amcr/particles.h"
#include "amcr/prototype_memory.h"
#include "amcr/random.h"
#include "amcr/recognition_result.h"
#include "amcr/track_registry.h"

namespace amcr
{
class Recognizer
{
public:
  /// Validates `params` (ParameterError) and takes a memory that must not be
  /// empty (MemoryError). The random generator is seeded with params.seed.
  Recognizer(const Params& params, std::shared_ptr<const PrototypeMemory> memory);

  /// Replaces the exploration policy (the default reflects at edges).
  void setPolicy(std::unique_ptr<ExplorationPolicy> policy);

  /// Swaps the memory and resets the filter.
  void setMemory(std::shared_ptr<const PrototypeMemory> memory);

  /// Forgets everything: particles are re-seeded at the next step, the
  /// generator is re-seeded with params.seed, the optical flow restarts.
  /// Track ids go on counting: none is reused in the recognizer's life.
  void reset();

  /// Processes the next frame (any type prepareScanImage takes; InputError
  /// otherwise): the V-particles ride the optical flow from the previous
  /// frame (params.optical_flow), then one iteration of paper 3.6 runs, or,
  /// under params.frame_budget_ms, as much of it as fits (the rest follows
  /// in the next frames). A change of image size re-seeds the V-particles.
  RecognitionResult step(const cv::Mat& image);

  /// Moves every V-particle by an external displacement (optical flow) without
  /// changing its correspondence: its M-particles stay where they are.
  /// `displacement` has one entry per V-particle (InputError otherwise).
  void moveVParticles(const std::vector<cv::Point2f>& displacement);

  // State, for overlays and diagnostics.
  const Params& params() const { return params_; }
  const PrototypeMemory& memory() const { return *memory_; }
  const std::vector<VParticle>& vParticles() const { return v_; }
  const MParticleSet& mParticles() const { return m_; }
  int mParticlesPerV() const { return static_cast<int>(slot_prototype_.size()); }
  /// The prototype of each of a V-particle's M-particle slots at seeding:
  /// the context prior (params.prototype_priors) as particle counts.
  const std::vector<int>& priorSlots() const { return slot_prototype_; }
  long iteration() const { return iteration_; }
  /// Each V-particle's densest M-cluster after the last step (index = V index).
  const std::vector<VParticleCluster>& clusters() const { return clusters_; }
  /// Each V-particle's position before the optical flow of the last step
  /// moved it (empty when the last step had no flow).
  const std::vector<cv::Point2f>& flowOrigins() const { return flow_origins_; }

private:
  /// A leading hypothesis whose implied poses are injected as M-particles.
  struct LeadingHypothesis
  {
    int prototype;
    Affine image_to_table;
  };

  /// Reads params_.prototype_priors against the memory (ParameterError for
  /// an unknown label or when every weight is 0) into the per-V slot table.
  void buildPriorSlots();
  /// A prototype drawn from the context prior.
  int drawPrototype();
  void seedAll(const RadialScanner& scanner);
  /// Moves the V-particles and the tracks by the optical flow into the
  /// current frame; returns how many V-particles were re-seeded because
  /// their flow failed.
  int followFlow(const RadialScanner& scanner);
  void seedV(VParticle& v, const RadialScanner& scanner);
  void seedMRange(MParticleSet& set, std::size_t begin, std::size_t end, const RaySignature& rays);
  void seedM(MParticleSet& set, std::size_t index, int prototype, const RaySignature& rays);
  void updateV(int v_index, const RadialScanner& scanner);
  void measureM(int v_index, const float* v_dist, const bool* v_valid);
  void resampleM(int v_index);
  void resampleV(const RadialScanner& scanner, const std::vector<RecognizedObject>& objects);
  void computeClusters();
  void feedVerification(const std::vector<RecognizedObject>& candidates);
  /// Fills `object` for a prototype at a table->image affine (score,
  /// support, correspondences, outline); false when the affine is out of bounds.
  bool describeObject(int prototype, const Affine& table_to_image, const RadialScanner& scanner,
                      RecognizedObject& object) const;
  std::vector<RecognizedObject> extractObjects(const RadialScanner& scanner);

  Params params_;
  std::shared_ptr<const PrototypeMemory> memory_;
  std::unique_ptr<ExplorationPolicy> policy_;
  ObservationModel observation_;
  MotionModel motion_;
  Rng rng_;

  int per_v_ = 0;  // M-particles per V-particle
  std::vector<int> slot_prototype_;   // prototype of each of a V-particle's M-particle slots (the prior)
  std::vector<int> active_;           // prototypes of non-zero prior weight
  std::vector<double> prior_cdf_;     // cumulative prior over active_; empty when uniform
  std::vector<VParticle> v_;
  MParticleSet m_;
  MParticleSet m_scratch_;
  std::vector<double> weight_scratch_;

  cv::Mat scan_image_;
  cv::Size image_size_;
  long iteration_ = 0;

  PyramidFlow flow_;
  std::vector<cv::Point2f> flow_origins_;
  int next_v_ = 0;               // the V-particle the current round goes on with (frame budget)
  double v_update_ms_ = 0.0;     // running estimates of the time of one V-particle's update
  double extraction_ms_ = 0.0;   // and of the result extraction, for the frame budget

  std::vector<VParticleCluster> clusters_;
  std::vector<LeadingHypothesis> leading_;  // injected at the next iteration
  TrackRegistry tracks_;  // the objects of the last step, moved by the flow
};
}  // namespace amcr
