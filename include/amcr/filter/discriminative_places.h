// Discriminative places, precomputed (the paper's section 4.3: "to
// automatically compare all pairs of prototype images and to find the
// discriminative locations"). Comparing all pairs of a 1,330-prototype
// memory would be 880,000 comparisons; only the pairs the radial-profile
// index confuses are compared. Places sampled from each prototype are looked
// up in the index, and a prototype whose answers keep naming another has it
// as a look-alike. The pair is aligned from those answers
// (prototype_alignment.h), and the places of each table from which the two
// prototypes predict the most different scans are kept: a V-particle
// deciding between the two (discriminative_attention.h) heads for the
// nearest one by a lookup, however far it lies.
#pragma once

#include <cstdint>
#include <vector>

#include "amcr/base/affine.h"

namespace amcr
{
class ObservationModel;
class Prototype;
class PrototypeMemory;

/// A place of a prototype's table from which its scan and its look-alike's
/// differ.
struct DiscriminativePlace
{
  float x = 0.f;           ///< table px of the pair's first prototype
  float y = 0.f;
  float divergence = 0.f;  ///< nats: the expected log-likelihood ratio of an 8-ray scan there, mean over headings
};

/// One ordered pair of look-alikes.
struct AlikePair
{
  int a = -1;                               ///< the prototype whose table the places are in
  int b = -1;                               ///< its look-alike
  Affine a_to_b = identityAffine();         ///< table px of a -> table px of b
  int confusions = 0;                       ///< sampled places of a or b whose index answers named the other
  std::vector<DiscriminativePlace> places;  ///< best first, at least kPlaceSpacing of a's size apart
};

/// How the look-alikes are found and their places chosen.
struct DiscriminativePlacesSettings
{
  int index_stride = 6;            ///< table px between the indexed places
  int samples = 48;                ///< places of each prototype looked up in the index
  int answers = 8;                 ///< index answers read per lookup
  int search = 16;                 ///< index places compared per lookup
  double min_confusion = 0.15;     ///< share of a prototype's looked-up places that must name the other
  int max_alike = 4;               ///< look-alikes kept per prototype, most confused first
  int places = 6;                  ///< places kept per ordered pair; 0: the pairs and their alignment only
  double min_divergence = 0.2;     ///< nats: a place where the scans differ less is not kept
  int threads = 1;                 ///< threads for the comparisons (the result does not depend on them)
};

/// The divergence, nats, between the 8-ray scans that prototype `a` and its
/// look-alike `b` (mapped by `a_to_b`) predict from a's table pixel (x, y),
/// averaged over the 9 headings of the 72 direction bins: per ray,
/// rayDivergence (discriminative_attention.h) of a's distance and b's
/// distance in a's px. Negative when (x, y) maps outside b's table.
double placeDivergence(const Prototype& a, const Prototype& b, const Affine& a_to_b,
                       const ObservationModel& observation, int x, int y);

/// The `count` places of a's table where placeDivergence is highest and at
/// least `min_divergence`, each a local best: no two closer than
/// kPlaceSpacing of a's longer side. Best first.
std::vector<DiscriminativePlace> discriminativePlaces(const Prototype& a, const Prototype& b, const Affine& a_to_b,
                                                      const ObservationModel& observation, int count,
                                                      double min_divergence);

/// Nearest two places of one pair may lie, as a share of the table's longer side.
constexpr double kPlaceSpacing = 1.0 / 6.0;

class DiscriminativePlaces
{
public:
  DiscriminativePlaces() = default;

  /// Compares the look-alikes of `memory` (prototypes whose `active` flag is
  /// set; all when empty) and keeps both orders of every aligned pair.
  static DiscriminativePlaces build(const PrototypeMemory& memory, const ObservationModel& observation,
                                    const DiscriminativePlacesSettings& settings,
                                    const std::vector<bool>& active = {});

  /// The pair (a, b), or null when b is not a look-alike of a.
  const AlikePair* find(int a, int b) const;

  /// Every pair whose first prototype is `a` (its look-alikes), most confused first.
  std::vector<const AlikePair*> lookAlikesOf(int a) const;

  const std::vector<AlikePair>& pairs() const { return pairs_; }

  /// The pairs as bytes (host byte order), for the table cache; fromBytes()
  /// gives them back, or throws MemoryError naming what does not fit (a
  /// prototype index of `prototypes` or more, bytes missing or left over).
  std::vector<std::uint8_t> toBytes() const;
  static DiscriminativePlaces fromBytes(const std::uint8_t* data, std::size_t size, int prototypes);

private:
  std::vector<AlikePair> pairs_;  // sorted by (a, b)
};
}  // namespace amcr
