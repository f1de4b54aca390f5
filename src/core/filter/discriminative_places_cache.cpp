#include "amcr/filter/discriminative_places_cache.h"

#include <cstdio>

#include <opencv2/core/version.hpp>

#include "amcr/base/content_hash.h"
#include "amcr/base/errors.h"
#include "amcr/filter/observation_model.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
std::string discriminativePlacesCacheName(std::uint64_t key)
{
  char name[48];
  std::snprintf(name, sizeof name, "places-%016llx.bin", static_cast<unsigned long long>(key));
  return name;
}

std::uint64_t discriminativePlacesKey(const PrototypeMemory& memory, const ObservationModel& observation,
                                      const DiscriminativePlacesSettings& settings, const std::vector<bool>& active)
{
  ContentHash hash;
  hash.addValue(kPlacesFormatVersion).addText(CV_VERSION).addValue(static_cast<std::uint64_t>(memory.size()));
  for (std::size_t i = 0; i < memory.size(); ++i)
  {
    const Prototype& p = memory[i];
    hash.addValue(p.width()).addValue(p.height()).addValue(p.tableStride());
    hash.add(p.rawDistances(0, 0), p.tableBytes());
    hash.addValue(static_cast<std::uint8_t>(active.empty() || active[i]));
  }
  hash.addValue(settings.index_stride).addValue(settings.samples).addValue(settings.answers).addValue(settings.search);
  hash.addValue(settings.min_confusion).addValue(settings.max_alike).addValue(settings.places);
  hash.addValue(settings.min_divergence);
  // The ray likelihoods the divergences are measured in (eqs. 5-6).
  for (int k = 0; k <= 200; ++k)
    hash.addValue(observation.logRay(0.25 * k));
  hash.addValue(observation.logInvalid());
  return hash.value();
}

std::shared_ptr<const DiscriminativePlaces> loadDiscriminativePlaces(
    const PrototypeMemory& memory, const ObservationModel& observation, const DiscriminativePlacesSettings& settings,
    const std::vector<bool>& active, const TableCache* cache, const std::function<void(const std::string&)>& warn)
{
  const std::uint64_t key = cache ? discriminativePlacesKey(memory, observation, settings, active) : 0;
  const std::string name = discriminativePlacesCacheName(key);
  if (cache)
  {
    std::vector<std::uint8_t> payload;
    std::string problem = cache->readPayload(name, key, payload);
    if (problem.empty() && !payload.empty())
    {
      try
      {
        return std::make_shared<const DiscriminativePlaces>(
            DiscriminativePlaces::fromBytes(payload.data(), payload.size(), static_cast<int>(memory.size())));
      }
      catch (const MemoryError& e)
      {
        problem = e.what();
      }
    }
    if (!problem.empty() && warn)
      warn("the cached look-alike pairs '" + name + "' were refused (" + problem + "): they are compared again");
  }
  auto places = std::make_shared<const DiscriminativePlaces>(
      DiscriminativePlaces::build(memory, observation, settings, active));
  if (cache)
  {
    const std::string problem = cache->writePayload(name, key, places->toBytes());
    if (!problem.empty() && warn)
      warn("the look-alike pairs are not cached: " + problem);
  }
  return places;
}
}  // namespace amcr
