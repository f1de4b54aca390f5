// The candidates checked against simpler explanations (generic_rivals.h):
// the parts of each outline that tell its prototype from an ellipse, its
// convex hull, its rectangle or a pair of lines must lie on the image's
// edges as well as the whole outline's score says.
#include <algorithm>
#include <cmath>

#include "amcr/base/homography.h"
#include "amcr/base/parallel_for.h"
#include "amcr/extraction/generic_rivals.h"
#include "amcr/extraction/homography_fit.h"
#include "amcr/extraction/outline_parts.h"
#include "extraction_steps.h"

namespace amcr
{
namespace extraction_steps
{
namespace
{
// A distinguishing point looks for its edge within this many score
// tolerances, as the score's points do (a wider search lets clutter's lines
// stand in for a stem). Points farther from the rival than kRivalApart
// searches distinguish the prototype from it (they cannot find the rival's
// own edge); a part of fewer than kMinRivalPoints points does not count, as
// with look-alikes (look_alike_support.cpp).
constexpr double kRivalSearch = 1.0;
constexpr double kRivalApart = 2.0;
constexpr int kMinRivalPoints = 6;
// A prototype whose body a round blob explains (its rival ellipse's axes
// within this ratio) may be fitted turned, its distinguishing part (a stem)
// off its edges while the body fits: its poses turned about the ellipse's
// centre by every kTurnStepDeg are tried, chosen with a search of
// kTurnSearch tolerances, then every degree about the best. An elongated one
// may be fitted half turned.
constexpr double kRoundAxisRatio = 1.15;
constexpr double kTurnStepDeg = 5.0;
constexpr double kTurnSearch = 3.0;

RivalVerdict verdictAt(const ExtractionInput& in, const Prototype& p, const std::vector<GenericRival>& rivals,
                       const Homography& table_to_image, double score_tolerance,
                       const std::vector<std::uint8_t>& covered = {})
{
  // The inner parts where the score counts them (outline_parts.h).
  std::vector<MappedPoint> mapped = mapOutline(p, table_to_image);
  fitPartsWithinShare(p, in.scanner, mapped, in.params.part_shift, score_tolerance);
  return verifyAgainstRivals(in.scanner, mapped, rivals, table_to_image,
                             kRivalSearch * score_tolerance, kRivalApart * kRivalSearch * score_tolerance,
                             kMinRivalPoints, covered);
}

/// x -> centre + R(angle) (x - centre), table px.
Affine turnAbout(const cv::Point2d& centre, double angle)
{
  const double c = std::cos(angle), s = std::sin(angle);
  return Affine(c, -s, centre.x - c * centre.x + s * centre.y, s, c, centre.y - s * centre.x - c * centre.y);
}

/// The prototype's rivals: from the cache, else fitted into `fitted`.
const std::vector<GenericRival>& rivalsOf(const ExtractionInput& in, int prototype,
                                          std::vector<GenericRival>& fitted)
{
  if (in.rivals != nullptr && in.rivals->has(prototype))
    return in.rivals->rivals(prototype);
  fitted = genericRivals(in.memory[prototype]);
  return fitted;
}
}  // namespace

void fitRivals(const ExtractionInput& in, const std::vector<FitStart>& starts, RivalCache& cache)
{
  if (!(in.params.rival_part_support > 0.0))
    return;
  std::vector<int> prototypes;
  for (const FitStart& start : starts)
    prototypes.push_back(start.prototype);
  cache.fit(in.memory, prototypes, in.num_threads);
}

RivalVerdict rivalVerdict(const ExtractionInput& in, int prototype, const Homography& table_to_image,
                          double score_tolerance, const std::vector<std::uint8_t>& covered)
{
  std::vector<GenericRival> fitted;
  return verdictAt(in, in.memory[prototype], rivalsOf(in, prototype, fitted), table_to_image, score_tolerance,
                   covered);
}

bool turnOntoDistinguishingParts(const ExtractionInput& in, int prototype_index, const Affine& table_to_image,
                                 double score_tolerance, Affine& turned)
{
  const Prototype& prototype = in.memory[prototype_index];
  std::vector<GenericRival> fitted;
  const std::vector<GenericRival>& rivals = rivalsOf(in, prototype_index, fitted);
  if (rivals.empty() || rivals[0].kind != GenericRival::Kind::kEllipse)
    return false;
  const RivalVerdict at_fit = verdictAt(in, prototype, rivals, liftAffine(table_to_image), score_tolerance);
  if (!at_fit.tested || at_fit.rival != GenericRival::Kind::kEllipse)
    return false;
  // The ellipse's centre and the ratio of its axes, from its polygon.
  cv::Point2d centre(0, 0);
  for (const cv::Point2d& q : rivals[0].points)
    centre += q;
  centre *= 1.0 / static_cast<double>(rivals[0].points.size());
  double nearest = 1e300, farthest = 0.0;
  for (const cv::Point2d& q : rivals[0].points)
  {
    const double r = std::hypot(q.x - centre.x, q.y - centre.y);
    nearest = std::min(nearest, r);
    farthest = std::max(farthest, r);
  }
  const bool round = farthest <= kRoundAxisRatio * nearest;
  // Coarse to fine: every kTurnStepDeg with a search kTurnSearch times the
  // tolerance (a part a few degrees off still finds its edges), then every
  // degree about the best turn with the tolerance itself.
  const auto turnedBy = [&](double degrees) {
    return composeAffine(turnAbout(centre, degrees * CV_PI / 180.0), table_to_image);
  };
  const auto supportAt = [&](double degrees, double tolerance) {
    return verdictAt(in, prototype, rivals, liftAffine(turnedBy(degrees)), tolerance).support;
  };
  const int turns = round ? static_cast<int>(std::lround(360.0 / kTurnStepDeg)) : 2;
  double coarse_best = -1.0, coarse_degrees = 0.0;
  for (int k = 1; k < turns; ++k)
  {
    const double degrees = 360.0 * k / turns, support = supportAt(degrees, kTurnSearch * score_tolerance);
    if (support > coarse_best)
    {
      coarse_best = support;
      coarse_degrees = degrees;
    }
  }
  const int fine = round ? static_cast<int>(kTurnStepDeg / 2) : 0;
  double best = at_fit.support;
  for (int d = -fine; d <= fine; ++d)
  {
    const double support = supportAt(coarse_degrees + d, score_tolerance);
    if (support > best)
    {
      best = support;
      turned = turnedBy(coarse_degrees + d);
    }
  }
  return best > at_fit.support;
}

void verifyRivals(const ExtractionInput& in, std::vector<Candidate>& candidates)
{
  if (!(in.params.rival_part_support > 0.0))
    return;
  const double could_report = kKeepTrackRatio * in.params.decision_threshold;
  parallelFor(static_cast<int>(candidates.size()), resolveThreads(in.num_threads), [&](int i) {
    Candidate& candidate = candidates[i];
    if (candidate.object.score < could_report)
      return;
    const int prototype = candidate.object.prototype_id;
    // The transform the object is reported with: its homography when used.
    const Homography table_to_image =
        composeHomography(liftAffine(in.memory[prototype].tableToOriginal()), candidate.object.homography);
    // Only the visible distinguishing parts count (covered_outline.h).
    const RivalVerdict verdict =
        rivalVerdict(in, prototype, table_to_image, candidate.score_tolerance, candidate.object.covered);
    candidate.object.rival_support = verdict.support;
    candidate.rival_hidden = verdict.hidden;
  });
}

bool passesRivals(const ExtractionParams& params, const Candidate& candidate, bool tracked)
{
  // What shows of a new object must tell it from its rivals; a tracked one
  // told itself apart when its track started.
  if (candidate.rival_hidden)
    return tracked;
  return candidate.object.rival_support >= params.rival_part_support * (tracked ? kKeepTrackRatio : 1.0);
}
}  // namespace extraction_steps
}  // namespace amcr
