#include "amcr/memory/table_stride_choice.h"

#include <algorithm>

#include "amcr/base/resource_bounds.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
std::int64_t maxTableBytesPerPrototype(int prototype_size, int table_stride)
{
  const std::int64_t stride = std::max(1, table_stride);
  const std::int64_t side = (prototype_size + 2LL * Prototype::tableMargin(prototype_size) + stride - 1) / stride;
  return side * side * kDirectionBins;
}

namespace
{
std::int64_t tableBytes(std::size_t prototype_count, const MemoryParams& params, int stride)
{
  return static_cast<std::int64_t>(prototype_count) * maxTableBytesPerPrototype(params.prototype_size, stride);
}

std::string describe(std::size_t prototype_count, const MemoryParams& params, int stride)
{
  return std::to_string(prototype_count) + " prototypes at prototype_size " + std::to_string(params.prototype_size) +
         " take up to " + formatBytes(static_cast<double>(tableBytes(prototype_count, params, stride))) +
         " of tables at table_stride " + std::to_string(stride);
}
}  // namespace

TableStrideChoice chooseTableStride(std::size_t prototype_count, const MemoryParams& params)
{
  const std::int64_t budget = static_cast<std::int64_t>(params.table_budget_mb) * 1'000'000;
  const std::string budget_text = "table_budget_mb " + std::to_string(params.table_budget_mb);
  TableStrideChoice choice;
  if (params.table_stride > 0)
  {
    choice.stride = params.table_stride;
    choice.table_bytes = tableBytes(prototype_count, params, choice.stride);
    choice.over_budget = choice.table_bytes > budget;
    choice.reason = "table_stride " + std::to_string(choice.stride) + " (given): " +
                    describe(prototype_count, params, choice.stride) +
                    (choice.over_budget ? ", above " + budget_text + "; table_stride 0 would choose a stride that fits"
                                        : ", within " + budget_text);
    return choice;
  }
  choice.stride = 1;
  while (choice.stride < Prototype::kMaxTableStride && tableBytes(prototype_count, params, choice.stride) > budget)
    ++choice.stride;
  choice.table_bytes = tableBytes(prototype_count, params, choice.stride);
  choice.over_budget = choice.table_bytes > budget;
  std::string why;
  if (choice.stride > 1)
    why = ": at table_stride " + std::to_string(choice.stride - 1) + " they would take up to " +
          formatBytes(static_cast<double>(tableBytes(prototype_count, params, choice.stride - 1))) + ", above " +
          budget_text;
  choice.reason = "table_stride " + std::to_string(choice.stride) + " (chosen, table_stride 0): " +
                  describe(prototype_count, params, choice.stride) +
                  (choice.over_budget ? ", above " + budget_text + " even at the largest stride" : ", within " + budget_text) +
                  why;
  return choice;
}
}  // namespace amcr
