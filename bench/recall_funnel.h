// The recall funnel: where, between a shape in view and its report, the recognizer loses it.
// After each step it follows each true object through the stages of Radial-AMCR (paper 3.6) and
// the result extraction, from the filter's state as it is (nothing in the recognizer changes):
//
//   on object  a V-particle lies on the object (inside its silhouette);
//   proposed   the proposal index, asked with such a V-particle's 8 rays, returns the true place
//              (the right prototype, where the V-particle lies in it, its heading), or a fresh
//              M-particle is there (seeded at this iteration, uniformly or from the index);
//   alive      such a V-particle holds a measured M-particle of the right prototype near the true
//              place (weighed by eq. 5 and kept by a resampling);
//   cluster    such a V-particle's dominant M-cluster is converged (cluster_min_share) on it;
//   verified   the extraction fitted and verified an object of the right label at the right place;
//   passed     its outline score reached the decision threshold (or it was reported);
//   reported   the step reported it (right label, right place).
//
// "Near": the true place within FunnelTolerance::table_px (table px) and the heading within
// heading_deg; "right place": every corner of the prototype within corner_share of the object's
// image diagonal, as the benchmark scores reports.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "amcr/recognizer.h"
#include "sequence_truth.h"

namespace amcr_bench
{
enum class FunnelStage
{
  kOnObject,
  kProposed,
  kAlive,
  kCluster,
  kVerified,
  kPassed,
  kReported,
};
constexpr int kFunnelStages = 7;
const char* stageName(FunnelStage stage);

struct FunnelTolerance
{
  double table_px = 8.0;      ///< a hypothesis's place off the truth, table px
  double heading_deg = 25.0;  ///< its heading off the truth, degrees
  double corner_share = 0.10; ///< a report's corner off the truth, share of the object's image diagonal
};

/// One true object in one frame.
struct ObjectFunnel
{
  std::string label;
  /// False when the memory does not hold the shape shown (no prototype of its label and size, or,
  /// among several instances of the label, none drawn from the truth's source image: an instance
  /// held out of it): the place stages cannot be judged, only the label's report.
  bool in_memory = false;
  int v_on = 0;         ///< V-particles on the object
  int v_indexable = 0;  ///< of those, with all 8 rays on an edge (what the index can be asked with)
  int v_proposed = 0;   ///< of those, whose index query returns the true place
  int best_rank = -1;   ///< the true place's rank among a query's candidates, best over V (0 = first); -1 none
  /// V-particles on the object with a fresh M-particle near the true place (seeded at this
  /// iteration's resampling, uniformly or from the index: proposed, not measured yet)
  int v_fresh = 0;
  /// V-particles on the object with a measured M-particle near the true place (it was weighed
  /// and survived a resampling)
  int v_alive = 0;
  int v_cluster = 0;    ///< V-particles on the object whose converged dominant cluster is the true place
  /// Of the right prototype's M-particles of V-particles on the object, the one nearest the true
  /// place: its distance (table px) and heading error (degrees); -1 when there is none.
  double best_table_px = -1.0;
  double best_heading_deg = -1.0;
  /// The largest share of a V-particle's M-particles near the true place (measured ones), over V on the object:
  /// how far the M-resampling concentrated the right hypothesis (cluster_min_share converges it).
  double best_share = 0.0;
  /// Of V-particles on the object with an M-particle near the true place, the smallest share of
  /// their M-particles more likely (the last update's eq. 5) than their best near one: 0 when the
  /// likelihood puts the truth first; -1 when no M-particle is near.
  double best_likelihood_quantile = -1.0;
  double candidate_score = -1.0;  ///< best outline score of a verified object at the right place; -1 none
  bool passed = false;
  bool reported = false;
  bool reached(FunnelStage stage) const;
};

/// The funnel of every object of `truth` after `recognizer` made `result` (its last step).
std::vector<ObjectFunnel> measureFunnel(const amcr::Recognizer& recognizer, const amcr::RecognitionResult& result,
                                        const TruthFrame& truth, const FunnelTolerance& tolerance = {});

/// A sequence's funnel for one object (the k-th of each frame's truth).
struct FunnelSummary
{
  std::string label;
  int frames = 0;                                ///< frames with truth
  std::array<int, kFunnelStages> reached{};      ///< frames that reached each stage
  std::array<int, kFunnelStages> first_frame{};  ///< the first (1-based) frame that did; 0 = never
  /// The first stage that no frame reached; -1 when every stage was reached in some frame.
  int first_missing = -1;
};

/// Accumulates the frames of one sequence.
class FunnelRecorder
{
public:
  /// Adds frame `frame` (0-based) of the sequence.
  void add(int frame, const std::vector<ObjectFunnel>& objects);
  const std::vector<FunnelSummary>& summaries() const { return summaries_; }

private:
  std::vector<FunnelSummary> summaries_;
};

/// One line of <sequence>.amcr.funnel.jsonl: {"frame": k, "objects": [...]}.
std::string funnelJson(int frame, const std::vector<ObjectFunnel>& objects);
/// Its last line: {"summary": [...]}, one entry per object.
std::string funnelSummaryJson(const std::vector<FunnelSummary>& summaries);
}  // namespace amcr_bench
