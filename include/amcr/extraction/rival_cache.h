// The generic rivals (generic_rivals.h) of a memory's prototypes, kept from
// frame to frame: they depend on the prototype alone, and fitting them anew
// each frame for every prototype a fit starts from cost about a tenth of a
// frame once the image's candidates (pose_votes.h) start fits of many
// prototypes. The owner clears it when its memory changes.
#pragma once

#include <cstddef>
#include <vector>

#include "amcr/extraction/generic_rivals.h"
#include "amcr/memory/prototype_memory.h"

namespace amcr
{
class RivalCache
{
public:
  /// Forgets every prototype's rivals (the memory changed).
  void clear();
  /// Fits the rivals of each of `prototypes` (indices into `memory`) not
  /// fitted yet, on `threads` threads. A memory of another size than the
  /// last call's clears the cache first.
  void fit(const PrototypeMemory& memory, const std::vector<int>& prototypes, int threads);
  /// Whether the rivals of prototype `index` are fitted.
  bool has(int index) const;
  /// The rivals of prototype `index`, as fit() left them (empty when not fitted).
  const std::vector<GenericRival>& rivals(int index) const;
  /// Prototypes whose rivals are kept.
  std::size_t fitted() const;

private:
  std::vector<std::vector<GenericRival>> rivals_;
  std::vector<bool> fitted_;
};
}  // namespace amcr
