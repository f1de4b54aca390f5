// A proposal index over the prototype tables (so that seeding does not fade
// as the memory grows, spec "Beyond the paper"; the data-driven
// proposals of Mixture-MCL, Thrun, Fox, Burgard & Dellaert 2001): for points
// of every prototype at a stride and every heading bin, the 8 feature rays
// the table holds there, described up to scale; a V-particle's own 8 rays,
// described the same way, find the (prototype, point, heading, scale) places
// of the whole memory that look like what it sees, by a nearest-neighbour
// search in a k-d tree (OpenCV's FLANN).
//
// The descriptor is the rays' log distances minus their mean: a similarity
// leaves it unchanged (the scale goes into the mean, a rotation by a multiple
// of the bin into the heading); an affine view changes it in proportion to
// its log anisotropy, so the index serves near-frontal views best and the
// uniform proposal keeps the rest.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/ray_directions.h"

namespace cv
{
namespace flann
{
class Index;
}
}  // namespace cv

namespace amcr
{
class TableCache;

/// The descriptor of 8 feature rays (see above).
using RayDescriptor = std::array<float, kFeatureRays>;

/// The descriptor of a V-particle's measured rays; false (and `out` left
/// alone) unless all 8 rays met an edge, none closer than 2 px.
bool describeRays(const RaySignature& rays, RayDescriptor& out);

/// The prototypes an index of a memory of `memory_size` holds, in memory
/// order: those `active` marks (a prior's active mask), every one when it is empty.
std::vector<int> indexedPrototypes(std::size_t memory_size, const std::vector<bool>& active);

/// One place of the memory that looks like a V-particle's scan.
struct ProposalCandidate
{
  int prototype = -1;
  float x = 0.f;         ///< table px
  float y = 0.f;         ///< table px
  int bin = 0;           ///< heading bin (ray_directions.h)
  float log_scale = 0;   ///< log(table px per input px) of the rays' mean
  float distance = 0;    ///< descriptor distance (L2, log units)
  /// The view shape the query assumed (xx, xy, yy; unsquashedFeatureRays): frontal for the
  /// V-particle's own rays.
  float shape[3] = {1.f, 0.f, 1.f};
};

class ProposalIndex
{
public:
  using WarningSink = std::function<void(const std::string&)>;

  /// Fewest places (indexed pixels with at least one heading whose 8 rays
  /// all meet an edge) a prototype needs to be indexed.
  static constexpr int kMinPlacesPerPrototype = 10;
  /// The largest stride max_entries can raise the index to, table px.
  static constexpr int kMaxIndexStride = 64;
  /// Prototypes sampled to choose the stride under max_entries.
  static constexpr std::size_t kBudgetSample = 64;

  /// Indexes every prototype of `memory` whose `active` flag is set (all when
  /// `active` is empty) at pixels `stride` table px apart; a prototype with
  /// fewer than kMinPlacesPerPrototype places at that stride at half of it,
  /// down to every pixel. A prototype that has too few even then (every
  /// pixel of it has a ray longer than the table holds: a large, round shape
  /// at a large prototype_size) is left out with a warning naming it; the
  /// uniform proposal still seeds it. Throws ParameterError for a stride
  /// below 1, MemoryError when no entry is left. With a `cache`, the k-d
  /// tree is read from it when it holds the tree of these very entries, and
  /// stored in it after a build (index_cache.h); a refused file or a failed
  /// write is a warning. When the entries would be more than `max_entries`
  /// (0 = no limit), the memory is indexed again at the smallest larger
  /// stride whose entries fit (their count falls with the stride's square),
  /// with a warning saying so; stride() gives the stride used.
  ProposalIndex(const PrototypeMemory& memory, int stride, const std::vector<bool>& active = {},
                const WarningSink& warn = WarningSink(), const TableCache* cache = nullptr,
                std::size_t max_entries = 0);
  ~ProposalIndex();
  ProposalIndex(const ProposalIndex&) = delete;
  ProposalIndex& operator=(const ProposalIndex&) = delete;

  /// The `k` entries nearest to the V-particle's rays (k-d tree search),
  /// nearest first; empty unless all 8 rays met an edge.
  std::vector<ProposalCandidate> query(const RaySignature& rays, int k) const;

  /// The same by exhaustive search: the reference the tests hold query() to.
  std::vector<ProposalCandidate> queryExact(const RaySignature& rays, int k) const;

  std::size_t size() const { return entries_.size(); }
  /// The stride the prototypes were indexed at (the constructor's, or a
  /// larger one under max_entries).
  int stride() const { return stride_; }
  /// Whether the k-d tree was read from the cache (not built).
  bool treeFromCache() const { return tree_from_cache_; }
  /// Labels of the prototypes left out of the index.
  const std::vector<std::string>& leftOut() const { return left_out_; }

private:
  struct Entry
  {
    int prototype;
    short x, y, bin;
    float log_mean;  // mean log table distance of the 8 rays
  };
  /// The entries of one prototype, and its places (pixels with an entry).
  struct Part
  {
    std::vector<Entry> entries;
    std::vector<RayDescriptor> rows;
    int places = 0;
  };
  /// The entries of prototype `p` at `stride`, or at a smaller stride
  /// where that leaves it too few places (see the constructor).
  static Part indexPrototype(const Prototype& prototype, int p, int stride);
  std::vector<ProposalCandidate> candidates(float query_log_mean, const std::vector<int>& indices,
                                            const std::vector<float>& dists) const;

  std::vector<Entry> entries_;
  cv::Mat descriptors_;  // one row per entry, CV_32F
  std::unique_ptr<cv::flann::Index> index_;
  std::vector<std::string> left_out_;
  int stride_ = 1;
  bool tree_from_cache_ = false;
};
}  // namespace amcr
