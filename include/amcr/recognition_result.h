// What the recognizer reports per frame (spec "Output").
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/affine.h"

namespace amcr
{
/// A V-particle's position and the mean of its winning M-cluster.
struct Correspondence
{
  cv::Point2d image;      ///< input px
  cv::Point2d prototype;  ///< px of the original prototype image
};

struct RecognizedObject
{
  std::string label;
  int prototype_id = -1;  ///< index into the memory
  int track_id = 0;       ///< stable while the object stays recognized, never reused in a run
  /// Share of the prototype's outline found on image edges after the affine
  /// fit, in [0, 1].
  double score = 0.0;
  int support = 0;  ///< V-particles that agree on this object
  Affine image_to_prototype;  ///< input px -> original prototype px
  Affine prototype_to_image;  ///< original prototype px -> input px
  std::vector<Correspondence> correspondences;
  std::vector<cv::Point2d> outline;  ///< the prototype's outline mapped into the input, px
};

/// The result of one Recognizer::step. Consumers take it as it is: the
/// objects are in their order, and time_ms is the step's time.
struct RecognitionResult
{
  long iteration = 0;         ///< complete iterations since the last reset
  double iterations = 0.0;    ///< share of an iteration run in this step (below 1 under a frame budget)
  /// Processing time of this step, ms, on the recognizer's clock (the one
  /// the frame budget uses): authoritative, there is no need to time step() again.
  double time_ms = 0.0;
  int flow_failures = 0;      ///< V-particles re-seeded because their optical flow failed
  int converged_v_particles = 0;  ///< V-particles with a focused M-cluster
  /// Only objects at or above the decision threshold, best score first (of
  /// equal scores, the one found first); no two outlines overlap by more
  /// than half (intersection over union).
  std::vector<RecognizedObject> objects;
};
}  // namespace amcr
