// Result extraction of the recognizer (spec "Output"): clusters, objects,
// their fit and score against the image, and the feedback the verification
// gives to attention (V-resampling) and to the M-particles (injection).
#include <algorithm>
#include <cmath>

#include "amcr/outline_fit.h"
#include "amcr/recognizer.h"

namespace amcr
{
namespace
{
constexpr double kVerifyTolerance = 2.0;           // px along the normal within which an outline point finds its edge
constexpr int kMaxLeadingHypotheses = 3;           // hypotheses whose poses are injected as M-particles
constexpr std::size_t kMaxVerifiedHypotheses = 8;  // groups checked against the image per iteration
constexpr double kKeepTrackRatio = 0.65;           // a tracked object stays at this share of the decision threshold
constexpr double kTrackDistance = 40.0;            // px an object's centre may move between frames and keep its track
constexpr double kVerificationGain = 4.0;          // log-weight per unit of outline score above 0.5 (V-resampling)
constexpr double kSameObjectOverlap = 0.5;         // outlines overlapping more are one object: the better is kept
}  // namespace

void Recognizer::computeClusters()
{
  const int prototypes = static_cast<int>(memory_->size());
  clusters_.resize(v_.size());
  for (std::size_t i = 0; i < v_.size(); ++i)
  {
    clusters_[i] = dominantCluster(m_, i * per_v_, (i + 1) * per_v_, prototypes, params_.cluster_radius);
    clusters_[i].v = static_cast<int>(i);
  }
}

bool Recognizer::describeObject(int prototype, const Affine& table_to_image, const RadialScanner& scanner,
                                RecognizedObject& object) const
{
  const Prototype& p = (*memory_)[prototype];
  double smallest = 0, largest = 0;
  affineScales(table_to_image, smallest, largest);
  Affine image_to_table;
  if (largest > params_.max_affine_scale || smallest < 1.0 / params_.max_affine_scale ||
      !invertAffine(table_to_image, image_to_table))
    return false;
  object = RecognizedObject();
  object.label = p.label();
  object.prototype_id = prototype;
  for (const auto& o : p.outline())
    object.outline.push_back(applyAffine(table_to_image, cv::Point2d(o.position)));
  // Too small to tell shapes apart: neither reported nor fed back to attention.
  if (outlineSize(object.outline) < params_.min_object_size)
    return false;
  object.score = outlineSupport(p, scanner, table_to_image, kVerifyTolerance);
  object.prototype_to_image = composeAffine(p.originalToTable(), table_to_image);
  object.image_to_prototype = composeAffine(image_to_table, p.tableToOriginal());
  // Support: the converged V-particles whose cluster this affine explains.
  for (const VParticleCluster& c : clusters_)
  {
    if (c.prototype != prototype || c.share < params_.cluster_min_share)
      continue;
    const cv::Point2d image_point(v_[c.v].x, v_[c.v].y);
    const cv::Point2d predicted = applyAffine(table_to_image, cv::Point2d(c.mean));
    if (std::hypot(predicted.x - image_point.x, predicted.y - image_point.y) > params_.group_tolerance)
      continue;
    object.correspondences.push_back({image_point, applyAffine(p.tableToOriginal(), cv::Point2d(c.mean))});
    object.v_particles.push_back(c.v);
  }
  object.support = static_cast<int>(object.correspondences.size());
  return true;
}

// Attention feedback from the verification: a converged V-particle whose
// interpretation the whole outline confirms gains V-weight, one whose
// interpretation the image contradicts loses it (the paper's V-weight,
// "V-particles on clutter die out", made explicit).
void Recognizer::feedVerification(const std::vector<RecognizedObject>& candidates)
{
  for (const VParticleCluster& c : clusters_)
  {
    if (c.share < params_.cluster_min_share)
      continue;
    double best = -1.0;
    for (const RecognizedObject& object : candidates)
    {
      if (object.prototype_id != c.prototype || object.score <= best)
        continue;
      const Prototype& p = (*memory_)[c.prototype];
      const cv::Point2d predicted = applyAffine(object.prototype_to_image, applyAffine(p.tableToOriginal(), cv::Point2d(c.mean)));
      if (std::hypot(predicted.x - v_[c.v].x, predicted.y - v_[c.v].y) <= params_.group_tolerance)
        best = object.score;
    }
    if (best >= 0.0)
      v_[c.v].log_evidence_sum += kVerificationGain * (best - 0.5);
  }
}

std::vector<RecognizedObject> Recognizer::extractObjects(const RadialScanner& scanner)
{
  computeClusters();
  // Every group is verified, even a single V-particle's: one that passes
  // seeds the others through injection before it has the support to be reported.
  std::vector<ObjectHypothesis> hypotheses = groupClusters(v_, clusters_, params_, 1);
  if (hypotheses.size() > kMaxVerifiedHypotheses)
    hypotheses.resize(kMaxVerifiedHypotheses);

  // Starting points of the fit: each group's affine, and each object of the
  // previous frame (recognition and tracking run together: a pose, once
  // fitted, is moved by the flow and refined on, not found again). A group near a previous object
  // of its prototype tries both and keeps the better fit.
  struct Start
  {
    int prototype;
    std::vector<Affine> affines;
  };
  std::vector<Start> starts;
  const std::vector<Track>& tracks = tracks_.tracks();
  std::vector<Affine> track_affines;  // each track's table -> image affine, moved by the flow
  for (const Track& t : tracks)
    track_affines.push_back(composeAffine((*memory_)[t.prototype_id].tableToOriginal(), t.prototype_to_image));
  std::vector<bool> track_used(tracks.size(), false);
  for (const auto& h : hypotheses)
  {
    Start start{h.prototype, {h.table_to_image}};
    const cv::Point2d centre = applyAffine(h.table_to_image, (*memory_)[h.prototype].centre());
    for (std::size_t k = 0; k < tracks.size(); ++k)
    {
      const cv::Point2d track_centre = applyAffine(track_affines[k], (*memory_)[h.prototype].centre());
      if (tracks[k].prototype_id == h.prototype &&
          std::hypot(centre.x - track_centre.x, centre.y - track_centre.y) <= kTrackDistance)
      {
        start.affines.push_back(track_affines[k]);
        track_used[k] = true;
      }
    }
    starts.push_back(std::move(start));
  }
  for (std::size_t k = 0; k < tracks.size(); ++k)
    if (!track_used[k])
      starts.push_back({tracks[k].prototype_id, {track_affines[k]}});

  std::vector<RecognizedObject> candidates;
  for (const auto& start : starts)
  {
    const Prototype& p = (*memory_)[start.prototype];
    RecognizedObject best;
    bool found = false;
    for (const Affine& affine : start.affines)
    {
      RecognizedObject object;
      const Affine refined = refineOnEdges(p, scanner, affine, params_.refine_iterations, params_.refine_search);
      if (describeObject(start.prototype, refined, scanner, object) && (!found || object.score > best.score))
      {
        best = std::move(object);
        found = true;
      }
    }
    if (found)
      candidates.push_back(std::move(best));
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const RecognizedObject& a, const RecognizedObject& b) { return a.score > b.score; });
  feedVerification(candidates);

  // The leading hypotheses seed M-particles at the next iteration, reported or not.
  leading_.clear();
  for (const auto& c : candidates)
  {
    if (static_cast<int>(leading_.size()) >= kMaxLeadingHypotheses || c.score < 0.5 * params_.decision_threshold)
      break;
    const Prototype& p = (*memory_)[c.prototype_id];
    leading_.push_back({c.prototype_id, composeAffine(c.image_to_prototype, p.originalToTable())});
  }

  // Report what passes the decision threshold; of two overlapping objects the better one.
  std::vector<RecognizedObject> objects;
  for (auto& c : candidates)
  {
    // Hysteresis: an object recognized in the previous frame stays while its
    // score keeps above a share of the threshold and one V-particle supports it.
    const bool tracked = tracks_.continues(c);
    const double threshold = params_.decision_threshold * (tracked ? kKeepTrackRatio : 1.0);
    if (c.score < threshold || c.support < (tracked ? 1 : params_.min_support))
      continue;
    bool suppressed = false;
    for (const auto& kept : objects)
      suppressed = suppressed || outlineOverlap(c.outline, kept.outline) > kSameObjectOverlap;
    if (suppressed)
      continue;
    objects.push_back(std::move(c));
  }
  return objects;
}
}  // namespace amcr
