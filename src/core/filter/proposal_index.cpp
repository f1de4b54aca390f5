#include "amcr/filter/proposal_index.h"

#include <algorithm>
#include <cmath>

#include <opencv2/flann.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"
#include "amcr/filter/index_cache.h"
#include "amcr/memory/table_cache.h"

namespace amcr
{
namespace
{
// Rays shorter than this (px) do not describe a place: a pixel on the
// outline's blurred edge sees that edge in every direction.
constexpr float kShortestRay = 2.f;
// One k-d tree with leaves of this many entries (FLANN's KDTreeSingleIndex):
// in 8 dimensions an exact search is fast enough, and the tree costs a few
// bytes per entry where FLANN's randomised forest took ~350 bytes.
constexpr int kLeafSize = 10;

/// Log distances minus their mean; the mean in `log_mean`.
void centre(const float log_distance[kFeatureRays], RayDescriptor& out, float& log_mean)
{
  float sum = 0.f;
  for (int k = 0; k < kFeatureRays; ++k)
    sum += log_distance[k];
  log_mean = sum / kFeatureRays;
  for (int k = 0; k < kFeatureRays; ++k)
    out[k] = log_distance[k] - log_mean;
}

bool describe(const RaySignature& rays, RayDescriptor& out, float& log_mean)
{
  float logs[kFeatureRays];
  for (int k = 0; k < kFeatureRays; ++k)
  {
    if (!(rays.distance[k] >= kShortestRay))
      return false;
    logs[k] = std::log(std::max(0.25f, rays.distance[k]));
  }
  centre(logs, out, log_mean);
  return true;
}

bool describeTable(const Prototype& prototype, int x, int y, int bin, RayDescriptor& out, float& log_mean)
{
  const std::uint8_t* raw = prototype.rawDistances(x, y);
  float logs[kFeatureRays];
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const std::uint8_t d = raw[(bin + k * kFeatureBinStep) % kDirectionBins];
    if (d == Prototype::kNoEdge || d * Prototype::kDistanceUnit < kShortestRay)
      return false;
    logs[k] = std::log(std::max(0.25f, d * Prototype::kDistanceUnit));
  }
  centre(logs, out, log_mean);
  return true;
}
}  // namespace

bool describeRays(const RaySignature& rays, RayDescriptor& out)
{
  float log_mean = 0.f;
  return describe(rays, out, log_mean);
}

std::vector<int> indexedPrototypes(std::size_t memory_size, const std::vector<bool>& active)
{
  std::vector<int> indexed;
  for (std::size_t p = 0; p < memory_size; ++p)
    if (active.empty() || active[p])
      indexed.push_back(static_cast<int>(p));
  return indexed;
}

ProposalIndex::ProposalIndex(const PrototypeMemory& memory, int stride, const std::vector<bool>& active,
                             const WarningSink& warn, const TableCache* cache, std::size_t max_entries)
{
  if (stride < 1)
    throw ParameterError("index_stride must be at least 1 table px, got " + std::to_string(stride));
  // Each prototype's entries into its own part, on OpenCV's threads
  // (parallel_for.h), then merged in prototype order: the index does not
  // depend on the thread count.
  const std::vector<int> indexed = indexedPrototypes(memory.size(), active);
  std::vector<Part> parts(indexed.size());
  const auto indexAll = [&](int at_stride) {
    std::size_t total = 0;
    parallelFor(static_cast<int>(indexed.size()), resolveThreads(0),
                [&](int i) { parts[i] = indexPrototype(memory[indexed[i]], indexed[i], at_stride); });
    for (const Part& part : parts)
      total += part.entries.size();
    return total;
  };
  // A budget that does not grow with the memory. Entries fall with the
  // square of the stride: the stride is first chosen from a sample of at
  // most kBudgetSample prototypes (indexing a large memory at a stride too
  // fine for it would take gigabytes), then raised again in the rare case
  // the whole memory still does not fit.
  const auto strideFor = [&](int from, double entries) {
    const double grow = std::sqrt(entries / static_cast<double>(max_entries));
    return std::min(kMaxIndexStride, std::max(from + 1, static_cast<int>(std::ceil(from * grow))));
  };
  stride_ = stride;
  double wanted = 0.0;  // the entries at `stride`: estimated from the sample, or counted
  if (max_entries > 0 && indexed.size() > kBudgetSample)
  {
    const std::size_t step = indexed.size() / kBudgetSample;
    std::vector<std::size_t> sampled(kBudgetSample, 0);
    parallelFor(static_cast<int>(kBudgetSample), resolveThreads(0), [&](int k) {
      sampled[k] = indexPrototype(memory[indexed[k * step]], indexed[k * step], stride).entries.size();
    });
    std::size_t sum = 0;
    for (std::size_t n : sampled)
      sum += n;
    wanted = static_cast<double>(sum) * static_cast<double>(indexed.size()) / kBudgetSample;
    if (wanted > static_cast<double>(max_entries))
      stride_ = strideFor(stride_, wanted);
  }
  std::size_t total = indexAll(stride_);
  if (stride_ == stride)
    wanted = static_cast<double>(total);
  while (max_entries > 0 && total > max_entries && stride_ < kMaxIndexStride)
  {
    stride_ = strideFor(stride_, static_cast<double>(total));
    total = indexAll(stride_);
  }
  if (stride_ != stride && warn)
    warn("the proposal index would hold about " + std::to_string(std::llround(wanted)) + " entries at index_stride " +
         std::to_string(stride) + ", more than index_max_entries (" + std::to_string(max_entries) +
         "): the memory is indexed at stride " + std::to_string(stride_) + " (" + std::to_string(total) + " entries)");
  // Merged in prototype order, each part freed once copied (a large
  // memory's parts run to gigabytes).
  std::size_t kept = 0;
  for (std::size_t i = 0; i < parts.size(); ++i)
    kept += parts[i].places < kMinPlacesPerPrototype ? 0 : parts[i].entries.size();
  entries_.reserve(kept);
  descriptors_.create(static_cast<int>(kept), kFeatureRays, CV_32F);
  int row = 0;
  for (std::size_t i = 0; i < parts.size(); ++i)
  {
    if (parts[i].places < kMinPlacesPerPrototype)
    {
      const std::string& label = memory[indexed[i]].label();
      left_out_.push_back(label);
      if (warn)
        warn("prototype '" + label + "' is left out of the proposal index: " + std::to_string(parts[i].places) +
             " of its pixels see an edge on all 8 rays within the table's reach (it needs " +
             std::to_string(kMinPlacesPerPrototype) + "); the uniform proposal still seeds it");
      continue;
    }
    entries_.insert(entries_.end(), parts[i].entries.begin(), parts[i].entries.end());
    for (const RayDescriptor& d : parts[i].rows)
      std::copy(d.begin(), d.end(), descriptors_.ptr<float>(row++));
    parts[i] = Part();
  }
  parts.clear();
  if (entries_.empty())
    throw MemoryError("the proposal index has no usable entry: no prototype has " +
                      std::to_string(kMinPlacesPerPrototype) +
                      " pixels whose 8 rays all meet an edge within the table's reach (set index_share to 0 to "
                      "work without it)");
  const std::uint64_t key = cache ? indexCacheKey(descriptors_, kLeafSize) : 0;
  if (cache)
  {
    std::string problem;
    index_ = readIndexTree(*cache, key, descriptors_, problem);
    if (!problem.empty() && warn)
      warn("the proposal index's cached tree '" + indexCacheName(key) + "' was refused (" + problem +
           "): it is built again");
    tree_from_cache_ = index_ != nullptr;
  }
  if (index_)
    return;
  cv::flann::IndexParams tree;
  tree.setAlgorithm(cvflann::FLANN_INDEX_KDTREE_SINGLE);
  tree.setInt("leaf_max_size", kLeafSize);
  tree.setBool("reorder", true);
  index_ = std::make_unique<cv::flann::Index>(descriptors_, tree);
  if (cache)
  {
    const std::string problem = writeIndexTree(*cache, key, *index_);
    if (!problem.empty() && warn)
      warn("the proposal index's tree is not cached: " + problem);
  }
}

ProposalIndex::~ProposalIndex() = default;

ProposalIndex::Part ProposalIndex::indexPrototype(const Prototype& prototype, int p, int stride)
{
  // A prototype with too few places at the stride (a small prototype_size,
  // a thin shape) is indexed at half the stride, down to every pixel.
  Part part;
  for (int at_stride = stride; at_stride >= 1; at_stride = at_stride == 1 ? 0 : std::max(1, at_stride / 2))
  {
    part = Part();
    for (const cv::Point& at : prototype.interior())
    {
      if (at.x % at_stride != 0 || at.y % at_stride != 0)
        continue;
      const std::size_t before = part.entries.size();
      for (int bin = 0; bin < kDirectionBins; ++bin)
      {
        RayDescriptor d;
        float log_mean = 0.f;
        if (!describeTable(prototype, at.x, at.y, bin, d, log_mean))
          continue;
        part.entries.push_back({p, static_cast<short>(at.x), static_cast<short>(at.y), static_cast<short>(bin), log_mean});
        part.rows.push_back(d);
      }
      part.places += part.entries.size() > before ? 1 : 0;
    }
    if (part.places >= kMinPlacesPerPrototype)
      break;
  }
  return part;
}

std::vector<ProposalCandidate> ProposalIndex::candidates(float query_log_mean, const std::vector<int>& indices,
                                                         const std::vector<float>& dists) const
{
  std::vector<ProposalCandidate> out;
  for (std::size_t i = 0; i < indices.size(); ++i)
  {
    if (indices[i] < 0 || indices[i] >= static_cast<int>(entries_.size()))
      continue;  // FLANN pads a short answer with -1
    const Entry& e = entries_[indices[i]];
    ProposalCandidate c;
    c.prototype = e.prototype;
    c.x = e.x;
    c.y = e.y;
    c.bin = e.bin;
    c.log_scale = e.log_mean - query_log_mean;
    c.distance = std::sqrt(std::max(0.f, dists[i]));
    out.push_back(c);
  }
  return out;
}

std::vector<ProposalCandidate> ProposalIndex::query(const RaySignature& rays, int k) const
{
  RayDescriptor d;
  float log_mean = 0.f;
  if (k < 1 || !describe(rays, d, log_mean))
    return {};
  k = std::min<int>(k, static_cast<int>(entries_.size()));
  std::vector<float> q(d.begin(), d.end());
  std::vector<int> indices(k, -1);
  std::vector<float> dists(k, 0.f);
  index_->knnSearch(q, indices, dists, k, cv::flann::SearchParams());
  return candidates(log_mean, indices, dists);
}

std::vector<ProposalCandidate> ProposalIndex::queryExact(const RaySignature& rays, int k) const
{
  RayDescriptor d;
  float log_mean = 0.f;
  if (k < 1 || !describe(rays, d, log_mean))
    return {};
  std::vector<std::pair<float, int>> all(entries_.size());
  for (int r = 0; r < descriptors_.rows; ++r)
  {
    const float* row = descriptors_.ptr<float>(r);
    float sum = 0.f;
    for (int j = 0; j < kFeatureRays; ++j)
      sum += (row[j] - d[j]) * (row[j] - d[j]);
    all[r] = {sum, r};
  }
  k = std::min<int>(k, static_cast<int>(all.size()));
  std::partial_sort(all.begin(), all.begin() + k, all.end());
  std::vector<int> indices(k);
  std::vector<float> dists(k);
  for (int i = 0; i < k; ++i)
  {
    dists[i] = all[i].first;
    indices[i] = all[i].second;
  }
  return candidates(log_mean, indices, dists);
}
}  // namespace amcr
