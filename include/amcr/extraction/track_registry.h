// The objects' life cycle in one place, so that every instance in view keeps
// one id from frame to frame: each reported object
// continues a track or starts one; a track is tentative when first seen,
// confirmed once reported in params.confirm_frames frames, held while it is
// confirmed, the tracker follows it and its score is at least the decision
// threshold (its V-particles may then look elsewhere; one that is reported
// only by the tracking hysteresis gets them back), and lost when its outline
// has been gone for params.lost_frames frames in a row or its centre left
// the image. Between, a track that is
// not reported coasts: the optical flow moves it and the next fit starts
// from it, and it keeps its id when it is found again. An object continues
// the track of its prototype whose outline (moved by the flow) overlaps it
// most. A track that ended is remembered for params.recall_frames frames: an
// object of its label that no live track takes and that overlaps its last
// outline continues it (its id and its record: a part that was missed for a
// while on a static scene is the same part). Ids are never given to another
// object within the registry's life.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/extraction/recognition_result.h"

namespace amcr
{
/// The thresholds of the life cycle (from TrackingParams, and the report's
/// of ExtractionParams).
struct LifecycleRule
{
  int confirm_frames = 3;   ///< reports that make a tentative object confirmed
  int lost_frames = 5;      ///< frames in a row without a report that end a track
  int recall_frames = 30;   ///< frames an ended track may still be continued (its id given back); 0 = never
  int max_objects = 64;     ///< tracks kept at once, coasting ones included
  double min_overlap = 0.3; ///< outline overlap (intersection over union) that continues a track
  double hold_score = 0.75; ///< score a confirmed object needs to be held (params.decision_threshold)
  /// rival_support below which a report of a track counts as a rival miss
  /// (kKeepTrackRatio of params.rival_part_support)
  double rival_keep_support = 0.29;

  LifecycleRule() = default;
  LifecycleRule(const TrackingParams& tracking, const ExtractionParams& extraction);
};

/// One object: as last reported (outline and pose moved by the flow since),
/// with its life-cycle record.
struct Track
{
  RecognizedObject object;  ///< working px; track_id and state are the track's
  int reports = 0;          ///< frames in which it was reported
  int misses = 0;           ///< frames in a row without a report (coasting)
  bool followed = false;    ///< the tracker moved it into the current frame
  /// Reports in a row whose rival_support was below rule.rival_keep_support:
  /// after kRivalGraceFrames of them the track is no longer reported.
  int rival_misses = 0;
};

class TrackRegistry
{
public:
  explicit TrackRegistry(const LifecycleRule& rule = LifecycleRule()) : rule_(rule) {}

  /// Sets the track id and the state of every object (a continued track's
  /// id, else a new one), counts a miss for every track no object continues,
  /// and ends the tracks that are lost: missed lost_frames times in a row,
  /// or (when `image` is not empty) with their outline's centre outside it.
  /// The ended tracks' objects, in state kLost, are appended to `ended`.
  void assign(std::vector<RecognizedObject>& objects, const cv::Size& image, std::vector<RecognizedObject>& ended);
  /// The same without the image test, dropping the ended tracks.
  void assign(std::vector<RecognizedObject>& objects);

  /// The track `object` would continue, or null.
  const Track* continued(const RecognizedObject& object) const;
  /// Whether a new object may start a track: fewer than max_objects are kept.
  bool hasRoom(int new_tracks = 0) const
  {
    return static_cast<int>(tracks_.size()) + new_tracks < rule_.max_objects;
  }

  /// Moves track `index` by an image motion between frames (its prediction
  /// from the optical flow); the track counts as followed into the frame.
  void move(std::size_t index, const Affine& motion);
  /// Counts every track as followed without a motion (a static scene: the
  /// recognizer runs without optical flow).
  void followAll();

  const std::vector<Track>& tracks() const { return tracks_; }

  /// The tracks that ended within the last recall_frames frames, as they ended.
  const std::vector<Track>& ended() const { return ended_; }

  /// Forgets the tracks, live and ended; ids go on counting, so none is reused.
  void clear();

private:
  /// Index of the track `object` continues, or -1; tracks marked in `taken`
  /// are not considered.
  int match(const RecognizedObject& object, const std::vector<bool>& taken) const;
  /// Index of the ended track `object` continues (the same label, the most
  /// overlap with its last outline, at least min_overlap), or -1.
  int recall(const RecognizedObject& object) const;
  /// Ages the ended tracks by a frame and forgets those past recall_frames.
  void ageEnded();

  LifecycleRule rule_;
  int next_id_ = 1;
  std::vector<Track> tracks_;
  std::vector<Track> ended_;  // misses counts the frames since the end
};

/// Intersection over union of the areas two closed outlines enclose (both
/// rasterised on a common grid of at most 64 x 64 cells).
double outlineOverlap(const std::vector<cv::Point2d>& a, const std::vector<cv::Point2d>& b);

/// The centre of the box around an outline (0, 0 for none).
cv::Point2d outlineCentre(const std::vector<cv::Point2d>& outline);
}  // namespace amcr
