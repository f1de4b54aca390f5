// The objects of the last frame and their track ids. An object keeps its id
// while it stays recognized: it is associated with the previous frame's
// object of the same prototype whose outline, moved by the optical flow,
// overlaps it most. Ids are never reused within the registry's life.
#pragma once

#include <vector>

#include "amcr/affine.h"
#include "amcr/recognition_result.h"

namespace amcr
{
/// One object of the last frame.
struct Track
{
  int id = 0;
  int prototype_id = -1;
  Affine prototype_to_image;          ///< original prototype px -> input px
  std::vector<cv::Point2d> outline;   ///< input px
};

class TrackRegistry
{
public:
  /// `min_overlap`: the outline overlap (intersection over union) an object
  /// needs with a previous one to continue its track.
  explicit TrackRegistry(double min_overlap = 0.3) : min_overlap_(min_overlap) {}

  /// Sets track_id of every object (a continued track's id, else a new one)
  /// and makes `objects` the tracks of the next frame.
  void assign(std::vector<RecognizedObject>& objects);

  /// Whether `object` would continue a track of the previous frame.
  bool continues(const RecognizedObject& object) const;

  /// Moves track `index` by an image motion between frames (its prediction
  /// from the optical flow).
  void move(std::size_t index, const Affine& motion);

  const std::vector<Track>& tracks() const { return tracks_; }

  /// Forgets the tracks; ids go on counting, so none is reused.
  void clear();

private:
  /// Index of the previous frame's track `object` continues, or -1; tracks
  /// marked in `taken` are not considered.
  int match(const RecognizedObject& object, const std::vector<bool>& taken) const;

  double min_overlap_;
  int next_id_ = 1;
  std::vector<Track> tracks_;
};

/// Intersection over union of the areas two closed outlines enclose (both
/// rasterised on a common grid of at most 64 x 64 cells).
double outlineOverlap(const std::vector<cv::Point2d>& a, const std::vector<cv::Point2d>& b);
}  // namespace amcr
