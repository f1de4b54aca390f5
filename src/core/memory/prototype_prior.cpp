#include "amcr/memory/prototype_prior.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
/// Each prototype's weight: its label's (1 unless params.prototype_priors
/// names the label) shared equally among the label's instances, so that a
/// label weighs the same whether one image or twenty show it.
std::vector<double> priorWeights(const PrototypeMemory& memory, const ParticleCounts& params)
{
  std::vector<double> weight(memory.size(), 1.0);
  for (const auto& prior : params.prototype_priors)
    if (memory.find(prior.first) < 0)
      throw ParameterError("prototype_priors names '" + prior.first + "', which is not a label of the memory");
  for (const std::string& label : memory.labels())
  {
    const auto named = params.prototype_priors.find(label);
    const double label_weight = named == params.prototype_priors.end() ? 1.0 : named->second;
    const std::vector<int> instances = memory.instancesOf(label);
    for (int p : instances)
      weight[p] = label_weight / static_cast<double>(instances.size());
  }
  return weight;
}

/// `slots` shared among the `active` prototypes in proportion to their
/// weights (largest remainder, so the shares add up exactly).
std::vector<int> shareSlots(int slots, const std::vector<int>& active, const std::vector<double>& weight, double total)
{
  std::vector<int> share(active.size());
  std::vector<std::pair<double, int>> remainder;
  int given = 0;
  for (std::size_t a = 0; a < active.size(); ++a)
  {
    const double exact = slots * weight[active[a]] / total;
    share[a] = static_cast<int>(std::floor(exact));
    given += share[a];
    remainder.emplace_back(exact - share[a], static_cast<int>(a));
  }
  std::stable_sort(remainder.begin(), remainder.end(), [](const auto& l, const auto& r) { return l.first > r.first; });
  for (int k = 0; given < slots; ++k, ++given)
    ++share[remainder[k % remainder.size()].second];
  return share;
}
}  // namespace

PrototypePrior::PrototypePrior(const PrototypeMemory& memory, const ParticleCounts& params)
{
  const std::vector<double> weight = priorWeights(memory, params);
  double total = 0.0;
  for (std::size_t p = 0; p < weight.size(); ++p)
    if (weight[p] > 0.0)
    {
      active_.push_back(static_cast<int>(p));
      total += weight[p];
    }
  if (active_.empty())
    throw ParameterError("prototype_priors gives every prototype of the memory weight 0");

  probability_.assign(weight.size(), 0.0);
  for (int p : active_)
    probability_[p] = weight[p] / total;
  // A budget that does not grow with the memory: the paper's count per prototype (kept as a mode,
  // m_particles_per_v 0) costs a memory of P prototypes P times as much (spec "Why recall fades").
  const int slots = params.m_particles_per_v > 0 ? params.m_particles_per_v
                                                 : params.m_particles_per_prototype * static_cast<int>(active_.size());
  const std::vector<int> share = shareSlots(slots, active_, weight, total);
  for (std::size_t a = 0; a < active_.size(); ++a)
    slots_.insert(slots_.end(), share[a], active_[a]);

  const bool uniform = std::all_of(active_.begin(), active_.end(), [&](int p) { return weight[p] == weight[active_[0]]; });
  if (!uniform)
  {
    double sum = 0.0;
    for (int p : active_)
      cdf_.push_back(sum += weight[p] / total);
  }
}

std::vector<bool> PrototypePrior::activeMask() const
{
  std::vector<bool> mask(probability_.size(), false);
  for (int p : active_)
    mask[p] = true;
  return mask;
}

int PrototypePrior::draw(Rng& rng) const
{
  if (cdf_.empty())
    return active_[rng.index(active_.size())];
  const double u = rng.uniform();
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  return active_[std::min<std::size_t>(it - cdf_.begin(), active_.size() - 1)];
}
}  // namespace amcr
