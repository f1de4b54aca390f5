// What the nodelet reports in its "recognizer" status on /diagnostics
// (diagnostic_updater): processing time per frame, dropped and skipped frames,
// overlays drawn, and the state of the filter (converged V-particles, leading
// hypotheses). The input's rate and delay are diagnostic_updater's own
// FrequencyStatus and TimeStampStatus (recognizer_ros.h).
// Thread-safe: the image callback records, the updater's timer reports.
#pragma once

#include <mutex>
#include <string>

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/time.h>

#include <amcr/Recognitions.h>

namespace amcr_ros
{
class RecognizerStats
{
public:
  /// An image arrived with this header sequence number (gaps count as dropped).
  void received(std::uint32_t seq);
  /// An image was refused (bad input, no prototypes).
  void skipped();
  /// An image was processed: its message, and the filter's state.
  struct FilterState
  {
    int converged_v_particles = 0;
    int num_v_particles = 0;
    int flow_failures = 0;     ///< V-particles re-seeded because their flow failed
    double mean_m_particles = 0.0;  ///< M-particles per V-particle, mean (KLD-sampling)
    double budget_ms = 0.0;    ///< ~frame_budget_ms, 0 = none
    int objects_over_limit = 0;  ///< objects found but not reported: max_objects tracks were kept
    int max_objects = 0;         ///< ~max_objects
  };
  void processed(const amcr::Recognitions& out, const FilterState& state);
  void overlayDrawn();
  /// The filter was reset or rebuilt; the sequence starts again.
  void restarted();
  void setPrototypes(std::size_t count, const std::string& problem);

  /// The status: ERROR without prototypes, WARN when no image arrived for
  /// `stale_after` s, some were skipped since the last report, or objects
  /// found since then were not reported (max_objects), OK otherwise.
  void report(diagnostic_updater::DiagnosticStatusWrapper& status, double stale_after = 5.0);

private:
  std::mutex mutex_;
  ros::WallTime last_arrival_;  // zero: none yet
  bool have_seq_ = false;
  std::uint32_t last_seq_ = 0;
  long received_ = 0, processed_ = 0, skipped_ = 0, dropped_ = 0, overlays_ = 0;
  long skipped_at_last_report_ = 0;
  double last_ms_ = 0.0, mean_ms_ = 0.0;
  long iteration_ = 0;
  int converged_ = 0, num_v_ = 0;
  double mean_m_particles_ = 0.0;
  double iterations_mean_ = 0.0, budget_ms_ = 0.0;
  long flow_failures_ = 0;
  long over_limit_ = 0, over_limit_at_last_report_ = 0;
  int max_objects_ = 0;
  std::string leading_;
  std::size_t prototypes_ = 0;
  std::string prototype_problem_;
};
}  // namespace amcr_ros
