// The frame budget (params.frame_budget_ms): running estimates of the time
// of one V-particle's update and of the result extraction decide whether one
// more update fits into the frame. Time comes from an injectable clock, so
// that a test can run the budget on a clock of its own.
#pragma once

#include <functional>

namespace amcr
{
/// A monotonic clock: the time now, ms (from any fixed origin).
using Clock = std::function<double()>;

/// std::chrono::steady_clock, ms.
Clock steadyClock();

class FrameBudget
{
public:
  /// `budget_ms` 0 (or less): no budget, every frame runs a whole round.
  explicit FrameBudget(double budget_ms);

  /// Replaces the clock (steadyClock() by default); the estimates stay.
  void setClock(Clock clock);

  double now() const { return clock_(); }

  /// Whether a budget applies.
  bool limited() const { return budget_ms_ > 0.0; }

  /// Whether, `elapsed_ms` into the frame, one more V-particle update and
  /// the extraction would end past the budget.
  bool exhausted(double elapsed_ms) const { return elapsed_ms + v_update_ms_ + extraction_ms_ > budget_ms_; }

  /// The estimates fall slowly and rise at once: a frame that ran over the
  /// budget makes the next frames careful. `updates` > 0.
  void recordUpdates(double elapsed_ms, int updates);
  void recordExtraction(double elapsed_ms);

  /// Forgets the estimates.
  void reset();

private:
  double budget_ms_;
  Clock clock_;
  double v_update_ms_ = 0.0;   // one V-particle's update
  double extraction_ms_ = 0.0; // the result extraction
};
}  // namespace amcr
