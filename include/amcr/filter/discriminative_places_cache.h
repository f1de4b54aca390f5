// The look-alike pairs and their discriminative places in the table cache
// (table_cache.h): finding them looks every prototype up in the index and
// aligns every confused pair, seconds for a large memory. They are stored as
// one cache file, named and keyed by the hash of every table they were
// compared on, the settings and the observation model, so a file can only be
// read back for the memory it was built from. A refused file (damaged,
// stale, of another format) is reported and the pairs are built again.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "amcr/filter/discriminative_places.h"

namespace amcr
{
class TableCache;

/// Changes whenever the comparison or the payload layout changes.
constexpr std::uint32_t kPlacesFormatVersion = 1;

/// The key of the pairs of `memory` (every table's bytes and size, the
/// `active` flags), `settings` but its thread count, the observation
/// model's ray likelihoods, kPlacesFormatVersion and the OpenCV version.
std::uint64_t discriminativePlacesKey(const PrototypeMemory& memory, const ObservationModel& observation,
                                      const DiscriminativePlacesSettings& settings, const std::vector<bool>& active);

/// The cache file of the pairs with `key` ("places-<key in hex>.bin").
std::string discriminativePlacesCacheName(std::uint64_t key);

/// The pairs read from `cache` (null: no cache) when its file with their
/// key holds them, else built (DiscriminativePlaces::build) and written
/// there. `warn` receives one line for a refused file or a failed write.
std::shared_ptr<const DiscriminativePlaces> loadDiscriminativePlaces(
    const PrototypeMemory& memory, const ObservationModel& observation, const DiscriminativePlacesSettings& settings,
    const std::vector<bool>& active, const TableCache* cache, const std::function<void(const std::string&)>& warn);
}  // namespace amcr
