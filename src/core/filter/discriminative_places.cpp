#include "amcr/filter/discriminative_places.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/filter/profile_index.h"
#include "amcr/filter/ray_divergence.h"
#include "amcr/filter/relational_update.h"
#include "amcr/memory/prototype_alignment.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr int kMinInliers = 6;                 // corresponding places a pair's alignment needs
constexpr double kAlignTolerance = 0.04;       // RANSAC tolerance, share of b's longer side
constexpr double kMaxOutlineDistance = 0.05;   // median outline distance of look-alikes, share of b's longer side
constexpr int kDivergenceGrid = 64;            // grid nodes along a table's longer side for the divergence map
// Another prototype's answer this much worse than the own prototype's best
// still confuses the two, and this much more (log units), for a place that
// matches itself exactly.
constexpr float kConfusableRatio = 1.5f;
constexpr float kConfusableSlack = 0.02f;

int longerSide(const Prototype& p) { return std::max(p.width(), p.height()); }

/// Where each of a's 72 direction bins points in b's table, and how many of
/// b's px one of a's px is along it: the linear part of a_to_b, once per pair.
struct MappedBins
{
  int bin[kDirectionBins];
  float b_per_a[kDirectionBins];

  explicit MappedBins(const Affine& a_to_b)
  {
    for (int k = 0; k < kDirectionBins; ++k)
    {
      const double c = std::cos(binToAngle(k)), s = std::sin(binToAngle(k));
      const double tx = a_to_b(0, 0) * c + a_to_b(0, 1) * s, ty = a_to_b(1, 0) * c + a_to_b(1, 1) * s;
      bin[k] = angleToBin(std::atan2(ty, tx));
      b_per_a[k] = static_cast<float>(std::hypot(tx, ty));
    }
  }
};

double divergenceAt(const Prototype& a, const Prototype& b, const Affine& a_to_b, const MappedBins& bins,
                    const ObservationModel& observation, int x, int y)
{
  const cv::Point q = nearestTablePixel(static_cast<float>(a_to_b(0, 0) * x + a_to_b(0, 1) * y + a_to_b(0, 2)),
                                        static_cast<float>(a_to_b(1, 0) * x + a_to_b(1, 1) * y + a_to_b(1, 2)));
  if (!insideTable(b, q))
    return -1.0;
  double sum = 0.0;
  for (int k = 0; k < kDirectionBins; ++k)
  {
    const float da = a.distance(x, y, k), db = b.distance(q.x, q.y, bins.bin[k]);
    const float db_in_a = (db < 0.f || bins.b_per_a[k] < 1e-6f) ? 0.f : std::max(1e-3f, db / bins.b_per_a[k]);
    sum += rayDivergence(da < 0.f ? 0.f : std::max(1e-3f, da), db_in_a, observation);
  }
  return sum / (kDirectionBins / kFeatureRays);  // one 8-ray scan per heading, 9 headings
}

/// A place of a table and the radial profile the table holds there.
struct SampledPlace
{
  cv::Point at;
  RadialProfile profile;
};

/// Up to `count` places of `p` spread over its table where the index can
/// answer (the profile is defined), in row order.
std::vector<SampledPlace> samplePlaces(const Prototype& p, int count)
{
  std::vector<SampledPlace> valid;
  const int step = std::max(1, longerSide(p) / 32);
  SampledPlace place;
  for (int y = step / 2; y < p.height(); y += step)
    for (int x = step / 2; x < p.width(); x += step)
      if (tableProfile(p, x, y, place.profile))
      {
        place.at = cv::Point(x, y);
        valid.push_back(place);
      }
  if (static_cast<int>(valid.size()) <= count)
    return valid;
  std::vector<SampledPlace> picked;
  for (int i = 0; i < count; ++i)
    picked.push_back(valid[static_cast<std::size_t>(i) * valid.size() / static_cast<std::size_t>(count)]);
  return picked;
}

/// What the index answered for one prototype's places about another.
struct Confusion
{
  int places = 0;                      ///< looked-up places whose answers named the other
  std::vector<cv::Point2d> here, there;  ///< corresponding places (this table, the other's)
};

/// The index's answers for prototype `a`'s sampled places, by the other prototype named.
std::map<int, Confusion> confusionsOf(const PrototypeMemory& memory, const ProfileIndex& index, int a,
                                      const DiscriminativePlacesSettings& settings, int& looked_up)
{
  std::map<int, Confusion> out;
  const std::vector<SampledPlace> places = samplePlaces(memory[a], settings.samples);
  looked_up = static_cast<int>(places.size());
  for (const SampledPlace& place : places)
  {
    const cv::Point& p = place.at;
    std::vector<int> named;
    const std::vector<ProposalCandidate> answers =
        index.query(memory, place.profile, settings.search, settings.answers);
    // The place is taken for another prototype when that one's answer fits
    // about as well as the best of its own prototype's (or the best at all):
    // in a small memory every answer list names others, alike or not.
    float own = std::numeric_limits<float>::infinity();
    for (const ProposalCandidate& c : answers)
      if (c.prototype == a)
        own = std::min(own, c.distance);
    if (answers.empty())
      continue;
    if (!std::isfinite(own))
      own = answers.front().distance;
    for (const ProposalCandidate& c : answers)
    {
      if (c.prototype == a || c.distance > kConfusableRatio * own + kConfusableSlack)
        continue;
      Confusion& confusion = out[c.prototype];
      confusion.here.emplace_back(p.x, p.y);
      confusion.there.emplace_back(c.x, c.y);
      if (std::find(named.begin(), named.end(), c.prototype) == named.end())
      {
        named.push_back(c.prototype);
        ++confusion.places;
      }
    }
  }
  return out;
}
}  // namespace

double placeDivergence(const Prototype& a, const Prototype& b, const Affine& a_to_b,
                       const ObservationModel& observation, int x, int y)
{
  if (x < 0 || y < 0 || x >= a.width() || y >= a.height())
    return -1.0;
  return divergenceAt(a, b, a_to_b, MappedBins(a_to_b), observation, x, y);
}

std::vector<DiscriminativePlace> discriminativePlaces(const Prototype& a, const Prototype& b, const Affine& a_to_b,
                                                      const ObservationModel& observation, int count,
                                                      double min_divergence)
{
  const MappedBins bins(a_to_b);
  const int step = std::max(1, longerSide(a) / kDivergenceGrid);
  std::vector<DiscriminativePlace> map;
  for (int y = step / 2; y < a.height(); y += step)
    for (int x = step / 2; x < a.width(); x += step)
    {
      const double d = divergenceAt(a, b, a_to_b, bins, observation, x, y);
      if (d >= min_divergence)
        map.push_back({static_cast<float>(x), static_cast<float>(y), static_cast<float>(d)});
    }
  // Best first; ties in row order, so the choice is the same on any machine.
  std::stable_sort(map.begin(), map.end(), [](const DiscriminativePlace& p, const DiscriminativePlace& q) {
    return p.divergence > q.divergence;
  });
  const double spacing = kPlaceSpacing * longerSide(a);
  std::vector<DiscriminativePlace> out;
  for (const DiscriminativePlace& p : map)
  {
    if (static_cast<int>(out.size()) >= count)
      break;
    bool apart = true;
    for (const DiscriminativePlace& q : out)
      apart = apart && std::hypot(p.x - q.x, p.y - q.y) >= spacing;
    if (apart)
      out.push_back(p);
  }
  return out;
}

DiscriminativePlaces DiscriminativePlaces::build(const PrototypeMemory& memory, const ObservationModel& observation,
                                                 const DiscriminativePlacesSettings& settings,
                                                 const std::vector<bool>& active)
{
  DiscriminativePlaces out;
  const int n = static_cast<int>(memory.size());
  const auto isActive = [&active](int i) { return active.empty() || active[static_cast<std::size_t>(i)]; };
  if (n < 2)
    return out;
  std::unique_ptr<ProfileIndex> index;
  try
  {
    index = std::make_unique<ProfileIndex>(memory, settings.index_stride, active);
  }
  catch (const MemoryError&)
  {
    return out;  // no prototype has places the index can hold: none is compared
  }

  // Each prototype's look-alikes: the prototypes its places are most often
  // taken for, kept when at least min_confusion of its places name them.
  std::vector<std::map<int, Confusion>> confusions(static_cast<std::size_t>(n));
  parallelFor(n, settings.threads, [&](int a) {
    if (!isActive(a))
      return;
    int looked_up = 0;
    std::map<int, Confusion> found = confusionsOf(memory, *index, a, settings, looked_up);
    std::vector<std::pair<int, int>> ranked;  // (-places, b): most confused first, then memory order
    for (const auto& entry : found)
      if (isActive(entry.first) && entry.second.places >= settings.min_confusion * std::max(1, looked_up))
        ranked.emplace_back(-entry.second.places, entry.first);
    std::sort(ranked.begin(), ranked.end());
    if (static_cast<int>(ranked.size()) > settings.max_alike)
      ranked.resize(static_cast<std::size_t>(std::max(0, settings.max_alike)));
    std::map<int, Confusion>& kept = confusions[static_cast<std::size_t>(a)];
    for (const auto& r : ranked)
      kept[r.second] = std::move(found[r.second]);
  });

  // Each unordered pair once, with the corresponding places of both sides.
  std::vector<std::pair<int, int>> unordered;
  for (int a = 0; a < n; ++a)
    for (const auto& entry : confusions[static_cast<std::size_t>(a)])
    {
      const int b = entry.first;
      if (a < b || confusions[static_cast<std::size_t>(b)].count(a) == 0)
        unordered.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(unordered.begin(), unordered.end());
  unordered.erase(std::unique(unordered.begin(), unordered.end()), unordered.end());

  std::vector<std::vector<AlikePair>> compared(unordered.size());
  parallelFor(static_cast<int>(unordered.size()), settings.threads, [&](int k) {
    const int a = unordered[static_cast<std::size_t>(k)].first, b = unordered[static_cast<std::size_t>(k)].second;
    std::vector<cv::Point2d> in_a, in_b;
    int confused = 0;
    const auto fromA = confusions[static_cast<std::size_t>(a)].find(b);
    if (fromA != confusions[static_cast<std::size_t>(a)].end())
    {
      in_a = fromA->second.here;
      in_b = fromA->second.there;
      confused += fromA->second.places;
    }
    const auto fromB = confusions[static_cast<std::size_t>(b)].find(a);
    if (fromB != confusions[static_cast<std::size_t>(b)].end())
    {
      in_a.insert(in_a.end(), fromB->second.there.begin(), fromB->second.there.end());
      in_b.insert(in_b.end(), fromB->second.here.begin(), fromB->second.here.end());
      confused += fromB->second.places;
    }
    const Prototype& pa = memory[a];
    const Prototype& pb = memory[b];
    PrototypeAlignment alignment;
    Affine b_to_a;
    if (!alignPrototypes(pa, pb, in_a, in_b, kAlignTolerance * longerSide(pb), kMinInliers,
                         kMaxOutlineDistance * longerSide(pb), alignment) ||
        !invertAffine(alignment.a_to_b, b_to_a))
      return;
    AlikePair ab, ba;
    ab.a = ba.b = a;
    ab.b = ba.a = b;
    ab.a_to_b = alignment.a_to_b;
    ba.a_to_b = b_to_a;
    ab.confusions = ba.confusions = confused;
    if (settings.places > 0)
    {
      ab.places = discriminativePlaces(pa, pb, ab.a_to_b, observation, settings.places, settings.min_divergence);
      ba.places = discriminativePlaces(pb, pa, ba.a_to_b, observation, settings.places, settings.min_divergence);
    }
    compared[static_cast<std::size_t>(k)] = {std::move(ab), std::move(ba)};
  });
  for (std::vector<AlikePair>& both : compared)
    for (AlikePair& pair : both)
      out.pairs_.push_back(std::move(pair));
  std::sort(out.pairs_.begin(), out.pairs_.end(),
            [](const AlikePair& p, const AlikePair& q) { return std::make_pair(p.a, p.b) < std::make_pair(q.a, q.b); });
  return out;
}

const AlikePair* DiscriminativePlaces::find(int a, int b) const
{
  const auto at = std::lower_bound(pairs_.begin(), pairs_.end(), std::make_pair(a, b),
                                   [](const AlikePair& p, const std::pair<int, int>& key) {
                                     return std::make_pair(p.a, p.b) < key;
                                   });
  return (at != pairs_.end() && at->a == a && at->b == b) ? &*at : nullptr;
}

std::vector<const AlikePair*> DiscriminativePlaces::lookAlikesOf(int a) const
{
  std::vector<const AlikePair*> out;
  for (auto at = std::lower_bound(pairs_.begin(), pairs_.end(), a,
                                  [](const AlikePair& p, int key) { return p.a < key; });
       at != pairs_.end() && at->a == a; ++at)
    out.push_back(&*at);
  std::stable_sort(out.begin(), out.end(),
                   [](const AlikePair* p, const AlikePair* q) { return p->confusions > q->confusions; });
  return out;
}
}  // namespace amcr
