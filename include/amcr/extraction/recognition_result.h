// What the recognizer reports per frame (spec "Output").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/homography.h"

namespace amcr
{
/// A V-particle's position and the mean of its winning M-cluster.
struct Correspondence
{
  cv::Point2d image;      ///< input px
  cv::Point2d prototype;  ///< px of the original prototype image
};

/// Where an object is in its life cycle (track_registry.h): first seen,
/// verified over frames, followed by the tracker (its V-particles released
/// to look elsewhere), or gone.
enum class ObjectState
{
  kTentative,  ///< reported in fewer than params.confirm_frames frames
  kConfirmed,  ///< reported in params.confirm_frames frames or more
  kHeld,       ///< confirmed, and the tracker followed it into this frame
  kLost,       ///< its track ended in this frame (RecognitionResult::lost only)
};

/// "tentative", "confirmed", "held", "lost".
std::string toString(ObjectState state);

struct RecognizedObject
{
  std::string label;       ///< what the object is (Prototype::label())
  std::string instance;    ///< which of the label's prototypes matched (Prototype::instance())
  int prototype_id = -1;  ///< index into the memory, of that instance
  int track_id = 0;       ///< stable while the object stays recognized, never reused in a run
  ObjectState state = ObjectState::kTentative;  ///< where the object is in its life cycle
  /// Share of the prototype's outline found on image edges after the fit
  /// (the homography's when homography_valid, else the affine's), in [0, 1].
  double score = 0.0;
  /// Of the outline points that tell the prototype from the simpler shapes
  /// that could explain it (generic_rivals.h), the share on edges; 1 when it
  /// has none to tell.
  double rival_support = 1.0;
  /// Share, in [0, 1], of the prototype's outline not covered by something
  /// in front of the object (covered_outline.h); the score is the share of
  /// this visible part on edges. 1 when nothing covers it.
  double visible_share = 1.0;
  int support = 0;  ///< V-particles that agree on this object
  Affine image_to_prototype;  ///< input px -> original prototype px
  Affine prototype_to_image;  ///< original prototype px -> input px
  /// Original prototype px -> input px, a perspective view (8 degrees of
  /// freedom), h22 = 1. When homography_valid is false it is the lift of
  /// prototype_to_image (rows of the affine, then 0 0 1), so it can always be used.
  Homography homography = liftAffine(identityAffine());
  /// True when the outline demanded the homography (perspective_choice.h) and
  /// it was used: outline, correspondences and score then follow it.
  bool homography_valid = false;
  /// Ratio of the larger to the smaller singular value of the linear part of
  /// prototype_to_image, >= 1 (1: not squashed).
  double anisotropy = 1.0;
  /// Angle between the target's normal and the viewing direction that the
  /// anisotropy implies for a planar target under weak perspective,
  /// acos(1 / anisotropy), degrees in [0, 90].
  double viewing_angle_deg = 0.0;
  /// Pairs whose prototype point the fitted transform maps within
  /// group_tolerance of the image point.
  std::vector<Correspondence> correspondences;
  /// The prototype's outline mapped into the input (by the homography when
  /// homography_valid, else the affine), px.
  std::vector<cv::Point2d> outline;
  /// Per point of `outline`, 1 where it is covered; empty when none is.
  std::vector<std::uint8_t> covered;
};

/// Maps the image side of `object` by an affine of the image (a motion
/// between frames, a change of resolution): outline, correspondences'
/// image points, both affines, the homography, anisotropy and viewing angle.
void mapImageSide(RecognizedObject& object, const Affine& image_map);

/// Where the time of one Recognizer::step went, ms on the recognizer's
/// clock; together about time_ms.
struct StepTimes
{
  double prepare_ms = 0.0;     ///< grey image, working scale, blur, the scanner
  double flow_ms = 0.0;        ///< pyramid, Lucas-Kanade, the V-particles' and tracks' moves (re-seeding included)
  double updates_ms = 0.0;     ///< the V-particles' iterations (paper 3.6)
  double extraction_ms = 0.0;  ///< clusters, fits, verification, tracks, attention, V-resampling
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
  StepTimes times;            ///< time_ms by phase
  int flow_failures = 0;      ///< V-particles re-seeded because their optical flow failed
  int converged_v_particles = 0;  ///< V-particles with a focused M-cluster
  double mean_m_particles = 0.0;  ///< M-particles per V-particle, mean (KLD-sampling adapts it)
  /// New objects found in this step (every check passed) but not reported:
  /// params.max_objects tracks were kept already. Not 0: raise max_objects.
  int objects_over_limit = 0;
  /// Only objects at or above the decision threshold, best score first (of
  /// equal scores, the one found first); no two outlines overlap by more
  /// than 0.3 (intersection over union).
  std::vector<RecognizedObject> objects;
  /// The tracks that ended in this step (state kLost): their outline gone
  /// for params.lost_frames frames in a row, or their centre left the image.
  /// Each as last reported, moved by the optical flow since; its track id
  /// is not reported again.
  std::vector<RecognizedObject> lost;
};
}  // namespace amcr
