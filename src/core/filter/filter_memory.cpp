// What a particle filter builds of a memory before it can use it: the prior,
// the proposal indexes and the look-alike pairs (filter_memory.h).
#include "amcr/filter/filter_memory.h"

#include <algorithm>
#include <cstdint>
#include <functional>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/filter/discriminative_places_cache.h"
#include "amcr/filter/observation_model.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
namespace
{
using WarningSink = std::function<void(const std::string&)>;

std::shared_ptr<const PrototypeMemory> checkedMemory(std::shared_ptr<const PrototypeMemory> memory)
{
  if (!memory || memory->empty())
    throw MemoryError("the recognizer needs a prototype memory with at least one prototype");
  return memory;
}

/// The prior, once the M-particles it asks for are within kMaxMParticles.
PrototypePrior checkedPrior(const PrototypeMemory& memory, const ParticleCounts& params)
{
  PrototypePrior prior(memory, params);
  if (params.m_particles_per_v > 0)
    return prior;  // the budget was checked with the parameters
  const std::int64_t active = static_cast<std::int64_t>(prior.slots().size()) / params.m_particles_per_prototype;
  checkParticleBound(params.num_v_particles, static_cast<std::int64_t>(prior.slots().size()),
                     std::to_string(params.m_particles_per_prototype) + " per prototype x " + std::to_string(active) +
                         " prototypes of non-zero prior");
  return prior;
}

/// The proposal index of `memory` under `prior` (null when index_share is 0).
std::shared_ptr<const ProposalIndex> buildIndex(const ProposalParams& params, const MemoryParams& tables,
                                                const PrototypeMemory& memory, const PrototypePrior& prior,
                                                const WarningSink& warn)
{
  if (params.index_share <= 0.0)
    return nullptr;
  // The k-d tree is cached beside the tables (table_cache_dir); the memory's
  // load has already reported a cache that cannot be used.
  const TableCache cache(tableCacheDirectory(tables.table_cache_dir));
  return std::make_shared<const ProposalIndex>(memory, params.index_stride, prior.activeMask(), warn,
                                               cache.readable() ? &cache : nullptr,
                                               static_cast<std::size_t>(params.index_max_entries));
}

/// The radial-profile index of `memory` under `prior` (null when index_share
/// is 0 or profile_index is off).
std::shared_ptr<const ProfileIndex> buildProfileIndex(const ProposalParams& params, const PrototypeMemory& memory,
                                                      const PrototypePrior& prior, const WarningSink& warn)
{
  if (params.index_share <= 0.0 || !params.profile_index)
    return nullptr;
  // One entry per place (the 8-ray index holds one per place and heading):
  // at half the 8-ray index's stride it is still the smaller.
  auto index = std::make_shared<const ProfileIndex>(memory, std::max(1, params.index_stride / 2), prior.activeMask());
  for (const std::string& label : index->leftOut())
    warn("prototype '" + label + "' is left out of the radial-profile index: too few of its pixels see an edge in "
         "nearly every direction within the table's reach; the 8-ray index still seeds it");
  return index;
}

/// The look-alike pairs of `memory` under `prior`, from the table cache when
/// it holds them (null when neither the moves nor the competing fits use them).
std::shared_ptr<const DiscriminativePlaces> buildPlaces(const Params& params, const PrototypeMemory& memory,
                                                        const PrototypePrior& prior, const WarningSink& warn)
{
  const bool moves_to_places = params.discriminative_moves && params.discriminative_places;
  if (!moves_to_places && params.competing_fits <= 0)
    return nullptr;
  // The competing fits need only the pairs and their alignment (a held
  // object's look-alikes are fitted where it lies); the places are for the moves.
  DiscriminativePlacesSettings settings;
  settings.places = moves_to_places ? settings.places : 0;
  settings.index_stride = params.index_stride;
  settings.threads = resolveThreads(params.num_threads);
  const TableCache cache(tableCacheDirectory(params.table_cache_dir));
  const ObservationModel observation(params);
  return loadDiscriminativePlaces(memory, observation, settings, prior.activeMask(),
                                  cache.readable() ? &cache : nullptr, warn);
}
}  // namespace

FilterMemory::FilterMemory(const Params& params, std::shared_ptr<const PrototypeMemory> memory)
  : params_(params), memory_(checkedMemory(std::move(memory))), prior_(checkedPrior(*memory_, params_))
{
  const WarningSink warn = [this](const std::string& line) { warnings_.push_back(line); };
  index_ = buildIndex(params_, params_, *memory_, prior_, warn);
  profile_index_ = buildProfileIndex(params_, *memory_, prior_, warn);
  places_ = buildPlaces(params_, *memory_, prior_, warn);
}
}  // namespace amcr
