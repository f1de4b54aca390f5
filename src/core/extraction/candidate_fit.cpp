// The candidates of the result extraction: each start's affines refined on
// the image's edges, described as an object (outline, score, support,
// correspondences) and verified; the best few fitted by a homography where
// the outline demands it (perspective_choice.h).
#include <algorithm>
#include <cmath>

#include "amcr/base/homography.h"
#include "amcr/base/parallel_for.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/perspective_choice.h"
#include "amcr/extraction/viewing_angle.h"
#include "amcr/memory/self_similar_turns.h"
#include "extraction_steps.h"

namespace amcr
{
namespace extraction_steps
{
namespace
{
constexpr std::size_t kMaxPerspectiveFits = 3;  // best candidates per frame that may get a homography
// A new object's fit that reaches this share of the decision threshold is
// tried again at its prototype's self-similar turns.
constexpr double kTurnedFitRatio = 0.6;
// A fit with covered points is refined again without them and without this
// share of the outline on either side of each covered run (where the
// occluder's contour crosses the outline, and the points find its edge); the
// new fit is taken when it claims covered points, unless its score drops by
// more than kRefitSlack (the first fit counted the occluder's contour as the
// object's).
constexpr double kBesideCovered = 0.03;
constexpr double kRefitSlack = 0.05;

/// A candidate for a prototype at a table -> image affine (score, support,
/// correspondences, outline); false when the affine is out of bounds or the
/// object too small. With a `perspective` whose homography is used, the
/// outline, the score and the correspondences follow the homography. With
/// `cluster_to_table`, the V-particles' cluster means are read through it
/// (clusters converged on a turn of the prototype onto itself).
bool describeObject(const ExtractionInput& in, int prototype, const Affine& table_to_image, Candidate& candidate,
                    const PerspectiveFit* perspective = nullptr, const Affine* cluster_to_table = nullptr)
{
  const Prototype& p = in.memory[prototype];
  double smallest = 0, largest = 0;
  affineScales(table_to_image, smallest, largest);
  Affine image_to_table;
  if (largest > in.max_affine_scale || smallest < 1.0 / in.max_affine_scale ||
      !invertAffine(table_to_image, image_to_table))
    return false;
  const bool use_homography = perspective != nullptr && perspective->used;
  const auto toImage = [&](const cv::Point2d& q) {
    return use_homography ? applyHomography(perspective->table_to_image, q) : applyAffine(table_to_image, q);
  };
  candidate = Candidate();
  candidate.table_to_image = table_to_image;
  RecognizedObject& object = candidate.object;
  object.label = p.label();
  object.instance = p.instance();
  object.prototype_id = prototype;
  for (const auto& o : p.outline())
    object.outline.push_back(toImage(cv::Point2d(o.position)));
  // Too small to tell shapes apart: neither reported nor fed back to attention.
  const double size = outlineSize(object.outline);
  if (size < in.params.min_object_size)
    return false;
  candidate.score_tolerance = verifyTolerance(size, in.params.verify_tolerance, in.params.verify_relative_tolerance);
  // The score of the visible outline (covered_outline.h); the homography's
  // was verified when it was chosen, with the same tolerance and rule.
  OutlineVerification verification =
      use_homography ? perspective->verification
                     : verifyOutline(p, in.scanner, table_to_image, candidate.score_tolerance, in.params.part_shift,
                                     in.params.min_visible_share < 1.0);
  object.score = verification.score;
  object.visible_share = verification.visible_share;
  object.covered = std::move(verification.covered);  // empty unless some are claimed
  candidate.covered_found = std::move(verification.covered_found);
  object.prototype_to_image = composeAffine(p.originalToTable(), table_to_image);
  object.image_to_prototype = composeAffine(image_to_table, p.tableToOriginal());
  object.homography_valid = use_homography;
  object.homography = use_homography ? composeHomography(liftAffine(p.originalToTable()), perspective->table_to_image)
                                     : liftAffine(object.prototype_to_image);
  object.anisotropy = affineAnisotropy(object.prototype_to_image);
  object.viewing_angle_deg = viewingAngleDegrees(object.anisotropy);
  // Support: the converged V-particles whose cluster this transform explains.
  const std::vector<VParticle>& v = in.v_particles;
  for (const VParticleCluster& c : in.clusters)
  {
    if (c.prototype != prototype || !c.converged)
      continue;
    const cv::Point2d image_point(v[c.v].x, v[c.v].y);
    const cv::Point2d mean = cluster_to_table ? applyAffine(*cluster_to_table, cv::Point2d(c.mean)) : cv::Point2d(c.mean);
    const cv::Point2d predicted = toImage(mean);
    if (!(std::hypot(predicted.x - image_point.x, predicted.y - image_point.y) <= in.params.group_tolerance))
      continue;
    object.correspondences.push_back({image_point, applyAffine(p.tableToOriginal(), mean)});
    candidate.v_particles.push_back(c.v);
  }
  object.support = static_cast<int>(object.correspondences.size());
  return true;
}

/// The flags of `covered` widened by `beside` points on either side (cyclic).
std::vector<std::uint8_t> widened(const std::vector<std::uint8_t>& covered, std::size_t beside)
{
  const std::size_t n = covered.size();
  std::vector<std::uint8_t> out(covered);
  for (std::size_t i = 0; i < n; ++i)
    if (covered[i] != 0 && (covered[(i + 1) % n] == 0 || covered[(i + n - 1) % n] == 0))
      for (std::size_t k = 1; k <= beside; ++k)
      {
        out[(i + k) % n] = 1;
        out[(i + n - k) % n] = 1;
      }
  return out;
}

/// A candidate with covered points fitted again on its visible outline
/// alone (covered_outline.h): the points under the occluder and beside it
/// take no part in the refinement (the first fit may have been pulled onto
/// the occluder's contour).
void refitVisible(const ExtractionInput& in, Candidate& candidate)
{
  const std::vector<std::uint8_t>& covered = candidate.covered_found;
  // A fit that could not lead (kLeadingScoreRatio) is not worth a refit.
  if (covered.empty() || candidate.object.score < kLeadingScoreRatio * in.params.decision_threshold)
    return;
  const int prototype = candidate.object.prototype_id;
  const Prototype& p = in.memory[prototype];
  const std::size_t beside = static_cast<std::size_t>(std::ceil(kBesideCovered * static_cast<double>(covered.size())));
  const Affine refined = refineOnEdges(p, in.scanner, candidate.table_to_image, in.params.refine_iterations,
                                       in.params.refine_search, widened(covered, beside));
  // Taken only as what it is for: a fit whose visible outline now claims
  // the rest covered (not one more refinement onto clutter).
  Candidate other;
  if (describeObject(in, prototype, refined, other) && other.object.visible_share < 1.0 &&
      other.object.score >= candidate.object.score - kRefitSlack)
    candidate = std::move(other);
}

/// A prototype whose body is round (an apple) may be fitted turned: the
/// body on its edges, the stem, which the refinement took for clutter, off
/// them. When the candidate could be reported but its distinguishing part
/// is not on edges, the pose turned about the body's centre that puts it
/// there best is refined and taken instead, if that part then verifies
/// and the whole could be reported.
void turnRoundShape(const ExtractionInput& in, Candidate& candidate)
{
  const double could_report = kKeepTrackRatio * in.params.decision_threshold;
  if (!(in.params.rival_part_support > 0.0) || candidate.object.score < could_report)
    return;
  const int prototype = candidate.object.prototype_id;
  const Prototype& p = in.memory[prototype];
  const RivalVerdict fitted =
      rivalVerdict(in, prototype, liftAffine(candidate.table_to_image), candidate.score_tolerance);
  Affine turned;
  if (fitted.support >= in.params.rival_part_support ||
      !turnOntoDistinguishingParts(in, prototype, candidate.table_to_image, candidate.score_tolerance, turned))
    return;
  Candidate other;
  const Affine refined = refineOnEdges(p, in.scanner, turned, in.params.refine_iterations, in.params.refine_search);
  if (!describeObject(in, prototype, refined, other) || other.object.score < could_report)
    return;
  // The turn was chosen among many for the edges its distinguishing part
  // finds, some of them clutter's: that part must then verify as a whole
  // outline must (decision_threshold), not just pass the rival check.
  const RivalVerdict verdict = rivalVerdict(in, prototype, liftAffine(refined), other.score_tolerance);
  if (verdict.support >= std::max(in.params.rival_part_support, in.params.decision_threshold))
    candidate = std::move(other);
}

/// A new object's fit may have converged on a turn of its prototype onto
/// itself (self_similar_turns.h: a square face whose ring of dots is nearly
/// symmetric, whose outline is then on edges and its dots just off them,
/// scoring below the decision or just above it): the fit started at each
/// such turn of the pose, refined, replaces the candidate when it scores
/// higher. Not a tracked object's: its turn was chosen when its track started.
void tryTurnedFits(const ExtractionInput& in, Candidate& candidate)
{
  if (candidate.object.score < kTurnedFitRatio * in.params.decision_threshold)
    return;
  const int prototype = candidate.object.prototype_id;
  const Prototype& p = in.memory[prototype];
  const Affine fitted = candidate.table_to_image;  // each turn of the first fit, not of a turned one
  for (const Affine& turn : selfSimilarTurns(p))
  {
    // The pose image(turn(q)): a cluster mean m of the fit's labelling is turn^-1(m) in this one.
    Affine unturn;
    if (!invertAffine(turn, unturn))
      continue;
    Candidate other;
    const Affine start = composeAffine(turn, fitted);
    const Affine refined = refineOnEdges(p, in.scanner, start, in.params.refine_iterations, in.params.refine_search);
    if (describeObject(in, prototype, refined, other, nullptr, &unturn) && other.object.score > candidate.object.score)
      candidate = std::move(other);
  }
}

/// The V-particles whose rays voted for a start's pose support its fit as
/// converged ones do (pose_votes.h: their rays match the prototype there),
/// each that lies on the fitted object, at the prototype point the fit puts
/// under it.
void addVoterSupport(const ExtractionInput& in, const std::vector<int>& voters, Candidate& candidate)
{
  const Prototype& p = in.memory[candidate.object.prototype_id];
  Affine image_to_table;
  if (!invertAffine(candidate.table_to_image, image_to_table))
    return;
  for (int k : voters)
  {
    if (std::find(candidate.v_particles.begin(), candidate.v_particles.end(), k) != candidate.v_particles.end())
      continue;
    const cv::Point2d image_point(in.v_particles[k].x, in.v_particles[k].y);
    const cv::Point2d table = applyAffine(image_to_table, image_point);
    const int x = cvRound(table.x), y = cvRound(table.y);
    if (x < 0 || y < 0 || x >= p.mask().cols || y >= p.mask().rows || p.mask().at<std::uint8_t>(y, x) == 0)
      continue;
    candidate.object.correspondences.push_back({image_point, applyAffine(p.tableToOriginal(), table)});
    candidate.v_particles.push_back(k);
  }
  candidate.object.support = static_cast<int>(candidate.object.correspondences.size());
}

/// The fit of the candidate's outline by a homography, when the outline
/// demands it (perspective_choice.h); the candidate is left as it is otherwise.
void fitPerspective(const ExtractionInput& in, Candidate& candidate)
{
  // Only an object that could be reported (as a tracked one) is worth it.
  if (!in.params.fit_homography || candidate.object.score < kKeepTrackRatio * in.params.decision_threshold)
    return;
  const int prototype = candidate.object.prototype_id;
  PerspectiveRule rule;
  rule.tolerance = candidate.score_tolerance;
  rule.part_shift = in.params.part_shift;
  rule.find_covered = in.params.min_visible_share < 1.0;
  rule.max_scale = in.max_affine_scale;
  const PerspectiveFit fit = choosePerspective(in.memory[prototype], in.scanner, candidate.table_to_image,
                                               candidate.object.score, in.params.refine_iterations,
                                               in.params.refine_search, rule);
  Candidate perspective;
  if (fit.used && describeObject(in, prototype, candidate.table_to_image, perspective, &fit))
    candidate = std::move(perspective);
}
}  // namespace

/// Each start refined on the image's edges and verified; of a start's
/// affines the best fit. Best score first (stable). The starts are fitted
/// in parallel (num_threads), each into its own slot, and kept in
/// their order: the same candidates whatever the thread count.
std::vector<Candidate> fitCandidates(const ExtractionInput& in, const std::vector<FitStart>& starts)
{
  const int threads = resolveThreads(in.num_threads);
  std::vector<Candidate> fitted(starts.size());
  std::vector<char> found(starts.size(), 0);
  parallelFor(static_cast<int>(starts.size()), threads, [&](int s) {
    const FitStart& start = starts[s];
    const Prototype& p = in.memory[start.prototype];
    for (const Affine& affine : start.affines)
    {
      Candidate candidate;
      const Affine refined = refineOnEdges(p, in.scanner, affine, in.params.refine_iterations, in.params.refine_search);
      const bool described = describeObject(in, start.prototype, refined, candidate);
      if (described)
      {
        refitVisible(in, candidate);
        turnRoundShape(in, candidate);
      }
      if (described &&
          (!found[s] || candidate.object.score > fitted[s].object.score))
      {
        fitted[s] = std::move(candidate);
        found[s] = 1;
      }
    }
    if (found[s] && !start.tracked)
      tryTurnedFits(in, fitted[s]);
    if (found[s] && !start.voters.empty())
      addVoterSupport(in, start.voters, fitted[s]);
    if (found[s])
      fitted[s].image_places = start.image_places;
  });
  std::vector<Candidate> candidates;
  for (std::size_t s = 0; s < starts.size(); ++s)
    if (found[s])
      candidates.push_back(std::move(fitted[s]));
  const auto byScore = [](const Candidate& a, const Candidate& b) { return a.object.score > b.object.score; };
  std::stable_sort(candidates.begin(), candidates.end(), byScore);
  // The homography, for the best few that could be reported (its fit costs
  // about as much as the rest of the extraction).
  parallelFor(static_cast<int>(std::min(candidates.size(), kMaxPerspectiveFits)), threads,
              [&](int i) { fitPerspective(in, candidates[i]); });
  std::stable_sort(candidates.begin(), candidates.end(), byScore);
  return candidates;
}
}  // namespace extraction_steps
}  // namespace amcr
