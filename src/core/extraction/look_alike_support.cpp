// Of alike shapes at one place the image decides where they differ: a
// candidate that verifies better than an overlapping, better supported
// look-alike there takes over the look-alike's V-particles (adoptSupport).
#include <algorithm>

#include "amcr/extraction/differing_parts.h"
#include "amcr/extraction/track_registry.h"
#include "extraction_steps.h"

namespace amcr
{
namespace extraction_steps
{
namespace
{
// Look-alikes (adoptSupport): outline points farther apart than this many
// score tolerances differ; a differing part of fewer points does not count;
// the edge support of one's differing part must beat the other's by the margin.
constexpr double kDifferingApart = 2.0;
constexpr int kMinDifferingPoints = 6;
constexpr double kDifferingPartsMargin = 0.25;
// A look-alike that verifies clearly (kClearWholeScore) and this much better
// on the whole outline wins whatever its differing part shows: a part of a
// few dozen points is read less surely than the whole, and one that
// verifies short of the decision threshold there while the whole verifies
// at 0.99 is still the better fit (one bird's other pose, on `similar`).
// Blobs of clutter, which a look-alike may fit a little better than the
// prototype they were taken for, rarely verify that well.
constexpr double kClearWholeMargin = 0.1;
constexpr double kClearWholeScore = 0.9;
// Look-alikes whose whole outlines verify within this of each other are a
// tie on the whole: their differing parts order them (adoptSupport).
constexpr double kWholeTie = 0.02;

/// Whether `better` verifies clearly and kClearWholeMargin better than
/// `supported` on the whole outline.
bool clearlyBetterOnTheWhole(const Candidate& better, const Candidate& supported)
{
  return better.object.score >= kClearWholeScore && better.object.score - supported.object.score >= kClearWholeMargin;
}

/// Whether `better`, which verifies at least as well as `supported` on the
/// whole outline, also does on the parts where the two outlines differ
/// (differing_parts.h): its own differing part verifies as an object must
/// (decision_threshold) and by kDifferingPartsMargin better than the other's.
bool winsOnDifferingParts(const ExtractionInput& in, const Candidate& better, const Candidate& supported)
{
  const double tolerance = std::max(better.score_tolerance, supported.score_tolerance);
  const DifferingParts parts = compareDifferingParts(
      in.scanner, mapOutline(in.memory[better.object.prototype_id], better.table_to_image),
      mapOutline(in.memory[supported.object.prototype_id], supported.table_to_image), tolerance,
      kDifferingApart * tolerance);
  // Its own differing part must be there on the image, as a whole outline
  // must be to be reported; the other's, where too small to count, is neutral.
  if (parts.a_points < kMinDifferingPoints || parts.a_support < in.params.decision_threshold)
    return false;
  const double supported_part = parts.b_points >= kMinDifferingPoints ? parts.b_support : 0.5;
  return parts.a_support - supported_part > kDifferingPartsMargin;
}
}  // namespace

// Of alike shapes at one place the image decides where they differ, not the
// count of V-particles: the M-particles of the V-particles on an object can
// settle in a look-alike prototype (a bird in another pose, or without its
// crest) while a competing cluster's fit (addCompetingStarts) verifies
// better. A candidate that overlaps a better supported one of another
// prototype, verifies at least as well on the whole outline and clearly
// better on the parts where the two differ (or clearly better on the whole),
// takes over its V-particles as support, each with the correspondence its
// own transform gives; report() then suppresses the other.
void adoptSupport(const ExtractionInput& in, std::vector<Candidate>& candidates)
{
  const std::vector<VParticle>& v = in.v_particles;
  // A tie on the whole outline (a bird with and without its crest, both on
  // its body's edges): the one that wins where they differ goes first, so
  // that it is the one that may adopt the other's support.
  for (std::size_t i = 0; i + 1 < candidates.size(); ++i)
  {
    Candidate& first = candidates[i];
    Candidate& second = candidates[i + 1];
    if (second.object.prototype_id != first.object.prototype_id &&
        first.object.score - second.object.score <= kWholeTie &&
        second.object.score >= in.params.decision_threshold &&
        outlineOverlap(first.object.outline, second.object.outline) > kSameObjectOverlap &&
        winsOnDifferingParts(in, second, first))
      std::swap(first, second);
  }
  for (std::size_t i = 0; i < candidates.size(); ++i)
  {
    Candidate& better = candidates[i];
    for (std::size_t j = i + 1; j < candidates.size(); ++j)  // best first: j scores no more than i, or ties
    {
      const Candidate& supported = candidates[j];
      if (supported.object.prototype_id == better.object.prototype_id ||
          supported.object.support <= better.object.support ||
          better.object.score < in.params.decision_threshold || !passesRivals(in.params, better, false) ||
          outlineOverlap(better.object.outline, supported.object.outline) <= kSameObjectOverlap ||
          !(clearlyBetterOnTheWhole(better, supported) || winsOnDifferingParts(in, better, supported)))
        continue;
      RecognizedObject& object = better.object;
      object.correspondences.clear();
      better.v_particles = supported.v_particles;
      for (int k : better.v_particles)
      {
        const cv::Point2d image_point(v[k].x, v[k].y);
        object.correspondences.push_back({image_point, applyAffine(object.image_to_prototype, image_point)});
      }
      object.support = static_cast<int>(object.correspondences.size());
      better.adopted = true;
    }
  }
}
}  // namespace extraction_steps
}  // namespace amcr
