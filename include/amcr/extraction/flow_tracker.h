// Recognition while tracking (spec "Tracking"): between frames the
// V-particles ride the optical flow, so each stays on the same object point
// and its M-particles (its places in the prototypes) stay valid; the objects
// of the last frame (the tracks) move with the flow along their outlines,
// which predicts where the next fit starts and which track an object
// continues. The tracker owns the image pyramids and the track registry; it
// moves no V-particle itself: it says where each one goes.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/params.h"
#include "amcr/extraction/optical_flow.h"
#include "amcr/extraction/recognition_result.h"
#include "amcr/extraction/track_registry.h"
#include "amcr/filter/particles.h"

namespace amcr
{
class FlowTracker
{
public:
  /// Reads flow_window, flow_levels and flow_max_error; the track registry
  /// follows `rule`.
  FlowTracker(const TrackingParams& params, const LifecycleRule& rule);

  /// Takes the next frame (8-bit grey).
  void push(const cv::Mat& gray8) { flow_.push(gray8); }

  /// Whether the flow from the previous frame can be computed.
  bool ready() const { return flow_.ready(); }

  /// Moves the tracks by the flow from the previous frame and returns where
  /// each V-particle of `v` goes (one move per V-particle, in index order):
  /// with the track it lies on, else with its own flow, else (an untextured
  /// place) as its nearest neighbours whose flow succeeded, else lost;
  /// `image_size` bounds the moves. Call when ready().
  std::vector<VParticleMove> follow(const std::vector<VParticle>& v, const cv::Size& image_size);

  /// Sets the objects' track ids and states, and appends the tracks that
  /// ended to `ended` (TrackRegistry::assign; `image`: the frame's size).
  void assign(std::vector<RecognizedObject>& objects, const cv::Size& image, std::vector<RecognizedObject>& ended)
  {
    tracks_.assign(objects, image, ended);
  }

  /// Counts every track as followed into the frame without moving it (no
  /// optical flow: a static scene).
  void holdStill() { tracks_.followAll(); }

  const TrackRegistry& tracks() const { return tracks_; }

  /// Forgets the tracks (ids go on counting).
  void clearTracks() { tracks_.clear(); }

  /// Forgets the pyramids and the tracks (ids go on counting).
  void reset();

private:
  PyramidFlow flow_;
  TrackRegistry tracks_;
};
}  // namespace amcr
