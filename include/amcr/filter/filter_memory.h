// A prototype memory made ready for a particle filter: the memory with its
// context prior, proposal indexes and look-alike pairs, built for one set of
// parameters. Building them is the slow part of a memory swap (seconds for a
// large memory). A FilterMemory touches no filter, so it can be built on one
// thread while a filter runs on another; ParticleFilter::setMemory and
// extendMemory (and the Recognizer's) then swap it in at once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "amcr/base/params.h"
#include "amcr/filter/discriminative_places.h"
#include "amcr/filter/profile_index.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/prototype_prior.h"

namespace amcr
{
class FilterMemory
{
public:
  /// Builds everything a filter with validated `params` needs of `memory`:
  /// its prior (ParameterError for priors naming a label the memory lacks,
  /// every weight 0, or too many M-particles), the proposal indexes (from
  /// the table cache when it holds them) and the look-alike pairs.
  /// MemoryError for a null or empty memory.
  FilterMemory(const Params& params, std::shared_ptr<const PrototypeMemory> memory);

  /// The parameters it was built for: a filter takes it only with the same ones.
  const Params& params() const { return params_; }
  const std::shared_ptr<const PrototypeMemory>& memory() const { return memory_; }
  /// The context prior over the memory's prototypes.
  const PrototypePrior& prior() const { return prior_; }
  /// The 8-ray proposal index; null when index_share is 0.
  const std::shared_ptr<const ProposalIndex>& index() const { return index_; }
  /// The radial-profile index; null when index_share is 0 or profile_index is off.
  const std::shared_ptr<const ProfileIndex>& profileIndex() const { return profile_index_; }
  /// The look-alike pairs; null when neither the discriminative moves nor competing fits use them.
  const std::shared_ptr<const DiscriminativePlaces>& places() const { return places_; }
  /// What the indexes' build left out (a line per prototype).
  const std::vector<std::string>& warnings() const { return warnings_; }

private:
  Params params_;
  std::shared_ptr<const PrototypeMemory> memory_;
  PrototypePrior prior_;
  std::shared_ptr<const ProposalIndex> index_;          // null when index_share is 0
  std::shared_ptr<const ProfileIndex> profile_index_;   // null when index_share is 0 or profile_index is off
  std::shared_ptr<const DiscriminativePlaces> places_;  // null when neither the moves nor competing fits use them
  std::vector<std::string> warnings_;
};
}  // namespace amcr
