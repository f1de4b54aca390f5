// Stable track ids across frames: an object keeps its id while it stays
// recognized; ids are never reused within a run.
#pragma once

#include <vector>

#include "amcr/recognition_result.h"

namespace amcr
{
class TrackRegistry
{
public:
  /// `max_distance`: how far, input px, an object's centre may move between
  /// two frames and keep its id.
  explicit TrackRegistry(double max_distance = 40.0) : max_distance_(max_distance) {}

  /// Sets track_id of every object: the id of the previous frame's object of
  /// the same prototype whose outline centre is nearest (within
  /// max_distance), else a new id.
  void assign(std::vector<RecognizedObject>& objects);

  /// Whether `object` would continue a track of the previous frame.
  bool continues(const RecognizedObject& object) const;

  void reset();

private:
  struct Track
  {
    int id;
    int prototype_id;
    cv::Point2d centre;
  };
  /// Index of the previous frame's track `object` continues, or -1;
  /// tracks marked in `taken` are not considered.
  int match(const RecognizedObject& object, const std::vector<bool>& taken) const;

  double max_distance_;
  int next_id_ = 1;
  std::vector<Track> tracks_;
};
}  // namespace amcr
