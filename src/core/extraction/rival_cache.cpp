#include "amcr/extraction/rival_cache.h"

#include <algorithm>

#include "amcr/base/parallel_for.h"

namespace amcr
{
void RivalCache::clear()
{
  rivals_.clear();
  fitted_.clear();
}

void RivalCache::fit(const PrototypeMemory& memory, const std::vector<int>& prototypes, int threads)
{
  if (rivals_.size() != memory.size())
  {
    rivals_.assign(memory.size(), {});
    fitted_.assign(memory.size(), false);
  }
  std::vector<int> missing;
  for (int p : prototypes)
    if (p >= 0 && static_cast<std::size_t>(p) < memory.size() && !fitted_[p] &&
        std::find(missing.begin(), missing.end(), p) == missing.end())
      missing.push_back(p);
  parallelFor(static_cast<int>(missing.size()), resolveThreads(threads),
              [&](int i) { rivals_[missing[i]] = genericRivals(memory[missing[i]]); });
  for (int p : missing)
    fitted_[p] = true;
}

bool RivalCache::has(int index) const
{
  return index >= 0 && static_cast<std::size_t>(index) < fitted_.size() && fitted_[index];
}

const std::vector<GenericRival>& RivalCache::rivals(int index) const
{
  static const std::vector<GenericRival> kNone;
  return index >= 0 && static_cast<std::size_t>(index) < rivals_.size() ? rivals_[index] : kNone;
}

std::size_t RivalCache::fitted() const { return static_cast<std::size_t>(std::count(fitted_.begin(), fitted_.end(), true)); }
}  // namespace amcr
