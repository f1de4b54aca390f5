// The lookup tables' stride chosen for a memory's size: the tables of a
// thousand prototypes at every pixel would take gigabytes, those of a few
// dozen a few tens of megabytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "amcr/base/params.h"

namespace amcr
{
/// The largest table one prototype at `prototype_size` and `table_stride`
/// can need, bytes: the square of its side with the margin in nodes, times
/// the direction bins.
std::int64_t maxTableBytesPerPrototype(int prototype_size, int table_stride = 1);

struct TableStrideChoice
{
  int stride = 1;               ///< the stride the tables are built at, table px [1, 4]
  std::int64_t table_bytes = 0; ///< most bytes the memory's tables take at `stride`
  bool over_budget = false;     ///< the tables may take more than params.table_budget_mb
  std::string reason;           ///< one line: the stride, why, and the tables' size
};

/// The stride of the tables of `prototype_count` prototypes. With
/// params.table_stride 0, the smallest stride whose tables fit
/// params.table_budget_mb (the largest, 4, when none does: over_budget);
/// otherwise params.table_stride, over_budget when it does not fit. The
/// size is the bound of maxTableBytesPerPrototype (a square prototype):
/// elongated shapes take less.
TableStrideChoice chooseTableStride(std::size_t prototype_count, const MemoryParams& params);
}  // namespace amcr
