// How much of its data a long recognition test runs.
//
// The plain build (scripts/test) runs every seed, case and frame a test lists. The sanitizer build
// (scripts/test --sanitize: CMake option AMCR_SANITIZE, which defines AMCR_SHORT_RUNS for the test
// binaries) runs a recognizer frame 5-20 times slower, and what it looks for, memory and
// undefined-behaviour faults, a short run reaches as well as a long one: the same code runs on every
// seed and every frame. There a test runs the first of its repeated seeds or cases only, or fewer
// frames where the later ones only repeat what its assertion has seen, and keeps every assertion,
// evaluated on what it ran (docs/testing.md, "Sanitizers").
#pragma once

#include <cstddef>
#include <vector>

namespace amcr_test
{
#ifdef AMCR_SHORT_RUNS
constexpr bool kShortRuns = true;
#else
constexpr bool kShortRuns = false;
#endif

/// `full` in the plain build, `short_run` in the sanitizer build: a count of seeds, cases or frames.
constexpr int runLength(int full, int short_run) { return kShortRuns ? short_run : full; }

/// All of `items` in the plain build, their first `short_count` in the sanitizer build.
template <typename T>
std::vector<T> firstOf(const std::vector<T>& items, std::size_t short_count)
{
  if (!kShortRuns || items.size() <= short_count)
    return items;
  return std::vector<T>(items.begin(), items.begin() + static_cast<std::ptrdiff_t>(short_count));
}
}  // namespace amcr_test
