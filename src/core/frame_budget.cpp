#include "amcr/frame_budget.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
constexpr double kEstimateDecay = 0.9;  // per frame, of the running cost estimates
}  // namespace

Clock steadyClock()
{
  return [] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
  };
}

FrameBudget::FrameBudget(double budget_ms) : budget_ms_(budget_ms), clock_(steadyClock()) {}

void FrameBudget::setClock(Clock clock)
{
  if (!clock)
    throw ParameterError("the clock of the frame budget must not be empty");
  clock_ = std::move(clock);
}

void FrameBudget::recordUpdates(double elapsed_ms, int updates)
{
  v_update_ms_ = std::max(kEstimateDecay * v_update_ms_, elapsed_ms / updates);
}

void FrameBudget::recordExtraction(double elapsed_ms)
{
  extraction_ms_ = std::max(kEstimateDecay * extraction_ms_, elapsed_ms);
}

void FrameBudget::reset()
{
  v_update_ms_ = 0.0;
  extraction_ms_ = 0.0;
}
}  // namespace amcr
