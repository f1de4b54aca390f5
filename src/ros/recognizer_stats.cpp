#include "recognizer_stats.h"

#include <cmath>
#include <cstdio>

#include <diagnostic_msgs/DiagnosticStatus.h>

#include "message_conversion.h"

namespace amcr_ros
{
void RecognizerStats::received(std::uint32_t seq)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++received_;
  if (have_seq_ && seq > last_seq_ + 1)
    dropped_ += seq - last_seq_ - 1;
  have_seq_ = true;
  last_seq_ = seq;
  last_arrival_ = ros::WallTime::now();
}

void RecognizerStats::skipped()
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++skipped_;
}

void RecognizerStats::processed(const amcr::Recognitions& out, const FilterState& state)
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++processed_;
  last_ms_ = out.processing_ms;
  mean_ms_ = processed_ == 1 ? out.processing_ms : 0.9 * mean_ms_ + 0.1 * out.processing_ms;
  iteration_ = out.iteration;
  iterations_mean_ = processed_ == 1 ? out.iterations : 0.9 * iterations_mean_ + 0.1 * out.iterations;
  converged_ = state.converged_v_particles;
  mean_m_particles_ = state.mean_m_particles;
  num_v_ = state.num_v_particles;
  flow_failures_ += state.flow_failures;
  over_limit_ += state.objects_over_limit;
  max_objects_ = state.max_objects;
  budget_ms_ = state.budget_ms;
  leading_.clear();
  for (const auto& o : out.objects)
  {
    char text[192];
    std::snprintf(text, sizeof(text), "%s%s #%d (%s, score %.2f, support %d)", leading_.empty() ? "" : ", ",
                  o.label.c_str(), o.track_id, stateName(o.state).c_str(), o.score, o.support);
    leading_ += text;
  }
}

void RecognizerStats::overlayDrawn()
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++overlays_;
}

void RecognizerStats::restarted()
{
  std::lock_guard<std::mutex> lock(mutex_);
  have_seq_ = false;
}

void RecognizerStats::setPrototypes(std::size_t count, const std::string& problem)
{
  std::lock_guard<std::mutex> lock(mutex_);
  prototypes_ = count;
  prototype_problem_ = problem;
}

void RecognizerStats::report(diagnostic_updater::DiagnosticStatusWrapper& status, double stale_after)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const bool stale = last_arrival_.isZero() || (ros::WallTime::now() - last_arrival_).toSec() > stale_after;

  if (prototypes_ == 0)
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                   "no prototypes loaded" + (prototype_problem_.empty() ? "" : ": " + prototype_problem_));
  else if (stale)
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no input image for " + std::to_string(stale_after) + " s");
  else if (skipped_ > skipped_at_last_report_)
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "input images skipped (see the log)");
  else if (over_limit_ > over_limit_at_last_report_)
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "objects found but not reported: max_objects (" + std::to_string(max_objects_) +
                       ") tracks are kept; raise ~max_objects");
  else
    status.summary(diagnostic_msgs::DiagnosticStatus::OK,
                   leading_.empty() ? "recognizing: nothing yet" : "recognized: " + leading_);
  skipped_at_last_report_ = skipped_;
  over_limit_at_last_report_ = over_limit_;

  status.add("prototypes", prototypes_);
  status.add("frames received", received_);
  status.add("frames processed", processed_);
  status.add("frames skipped (bad input)", skipped_);
  status.add("frames dropped (sequence gaps)", dropped_);
  status.add("overlays drawn", overlays_);
  status.add("processing time, last (ms)", last_ms_);
  status.add("processing time, mean (ms)", mean_ms_);
  status.add("iteration", iteration_);
  status.add("iterations per frame, mean", iterations_mean_);
  status.add("frame budget (ms)", budget_ms_ > 0.0 ? std::to_string(budget_ms_) : std::string("none"));
  status.add("frame budget used, mean (%)", budget_ms_ > 0.0 ? 100.0 * mean_ms_ / budget_ms_ : 0.0);
  status.add("V-particles re-seeded by failed flows", flow_failures_);
  status.add("objects not reported over max_objects", over_limit_);
  status.add("converged V-particles", std::to_string(converged_) + " of " + std::to_string(num_v_));
  status.add("M-particles per V-particle (mean)", static_cast<int>(std::lround(mean_m_particles_)));
  status.add("leading hypotheses", leading_.empty() ? "none" : leading_);
}
}  // namespace amcr_ros
