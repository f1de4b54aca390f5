// A picture of the recognizer's state, as in the paper's figures: the input
// image with the V-particles and the recognized outlines, and beside it the
// prototypes with the M-particles and the correspondence lines.
//
//   cv::Mat frame = amcr::drawOverlay(image, recognizer, recognizer.step(image));
//
// Core library: OpenCV only. The offline runner writes these frames to a
// video; the nodelet publishes them.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/extraction/recognition_result.h"
#include "amcr/filter/filter_view.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"

namespace amcr
{
struct OverlayOptions
{
  /// The prototype column may take at most this share of the input width;
  /// within it the panels are laid out in a grid as large as fits (0, 4].
  double max_column_fraction = 0.5;
  /// Panels are never smaller than this, px (the column then grows wider).
  int min_panel_size = 64;
  int v_radius = 4;            ///< circle of a V-particle, px of the input
  int heading_length = 10;     ///< heading tick of a V-particle, px of the input
  int m_dot_radius = 1;        ///< dot of an M-particle, px of the panel
  bool draw_v_particles = true;
  bool draw_m_particles = true;
  bool draw_correspondences = true;
  /// The outlines of the look-alike clusters each V-particle decides between.
  bool draw_competing = true;
  bool draw_status = true;     ///< iteration, time and counts in the top-left corner
};

/// The layout of an overlay. It depends only on the input size, the number of
/// prototypes and the options, so every frame of a stream has the same size
/// (video writers need it).
struct OverlayLayout
{
  cv::Size size;        ///< the whole overlay, both sides even (codecs need it)
  cv::Rect image;       ///< where the input is drawn (top-left, 1:1)
  cv::Rect column;      ///< the prototype column, right of the input
  int grid_columns = 0;
  int grid_rows = 0;
  int cell = 0;         ///< side of one square panel cell, px

  /// The cell of prototype `index` (row-major in the grid).
  cv::Rect cellRect(int index) const;
};

OverlayLayout overlayLayout(const cv::Size& input_size, std::size_t num_prototypes,
                            const OverlayOptions& options = OverlayOptions());

/// Draws the overlay of one step from the filter's view (Recognizer::view())
/// and the `result` the step returned for `input`. `input` is any image type
/// that prepareScanImage takes: 8-bit images keep their colour, others are
/// shown in grey. Returns a CV_8UC3 BGR image of
/// overlayLayout(input.size(), memory size).size. Throws InputError for an
/// empty or unsupported image.
///
/// Colours: a V-particle's circle has the colour of its dominant prototype
/// (the prototype of its converged M-cluster, as the result extraction
/// decides; the same colour frames that prototype's panel), or grey when its
/// M-particles have not converged; its heading tick has the V-particle's own
/// colour, which its M-particle dots share in the panels. A white line
/// shows where the optical flow of the step took a V-particle from. Thin
/// dashed outlines in their prototypes' colours show the look-alike
/// clusters a V-particle is deciding between (discriminative_attention.h),
/// and a white ring marks it when its move was chosen to decide them
/// (discriminative_moves).
/// Recognized objects and their correspondence lines have one colour per track.
cv::Mat drawOverlay(const cv::Mat& input, const PrototypeMemory& memory, const FilterView& view,
                    const RecognitionResult& result, const OverlayOptions& options = OverlayOptions());

/// The same with the recognizer's memory and view.
cv::Mat drawOverlay(const cv::Mat& input, const Recognizer& recognizer, const RecognitionResult& result,
                    const OverlayOptions& options = OverlayOptions());

/// The label the overlay draws above an object, one string per line:
/// "label #track score (support)", then "view <viewing angle>deg
/// <anisotropy>:1", with " persp" when the homography is used; the first
/// ends in " vis <visible share>%" when something covers part of the object.
std::vector<std::string> objectLabel(const RecognizedObject& object);

/// The colour of prototype `index` (BGR), as used in the overlay.
cv::Scalar prototypeColour(int index);
/// The colour of V-particle `index` (BGR), shared by its M-particles.
cv::Scalar vParticleColour(int index);
}  // namespace amcr
