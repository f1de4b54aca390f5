// The steps of the result extraction (extractObjects, object_extractor.cpp)
// and what they share: where the fits start (fit_starts.cpp), the candidates
// fitted and verified on the image (candidate_fit.cpp), and the support a
// look-alike takes over (look_alike_support.cpp). Private to src/core.
#pragma once

#include <vector>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/extraction/object_extractor.h"

namespace amcr
{
namespace extraction_steps
{
constexpr double kKeepTrackRatio = 0.65;  // a tracked object stays at this share of the decision threshold
// Outlines overlapping more are one object: the better is kept. Below a half
// (an elongated part found twice, slid along its axis, overlaps itself by a
// third); touching copies overlap by next to nothing.
constexpr double kSameObjectOverlap = 0.3;

/// An object verified on the image, with the V-particles that support it.
struct Candidate
{
  RecognizedObject object;
  std::vector<int> v_particles;  // V indices, one per correspondence
  Affine table_to_image;         // the fitted affine, table px -> input px
  double score_tolerance = 0.0;  // px: the score's tolerance at the object's size
  bool adopted = false;          // took over a look-alike's V-particles (adoptSupport)
};

/// Where the fit of one prototype starts: a group's affine and the affines
/// of the previous frame's objects near it (table -> image).
struct FitStart
{
  int prototype;
  std::vector<Affine> affines;
};

/// What every step of the extraction reads.
struct ExtractionInput
{
  const ParticleFilter& filter;
  const RadialScanner& scanner;
  const std::vector<VParticleCluster>& clusters;
  const Params& params;
  const PrototypeMemory& memory;
};

/// Where the fits start: each group of clusters, each tracked object, and
/// the competing interpretations (fit_starts.cpp).
std::vector<FitStart> fitStarts(const ExtractionInput& in, const TrackRegistry& registry);

/// Each start refined on the image's edges and verified, best score first
/// (candidate_fit.cpp).
std::vector<Candidate> fitCandidates(const ExtractionInput& in, const std::vector<FitStart>& starts);

/// A candidate that verifies better than an overlapping look-alike where
/// the two differ takes over its support (look_alike_support.cpp).
void adoptSupport(const ExtractionInput& in, std::vector<Candidate>& candidates);
}  // namespace extraction_steps
}  // namespace amcr
