#include "amcr/filter/profile_index.h"

#include <algorithm>
#include <cmath>

#include <opencv2/flann.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/parallel_for.h"

namespace amcr
{
namespace
{
constexpr float kShortestRay = 2.f;  // px; as the 8-ray index
constexpr int kLeafSize = 10;        // k-d tree leaves, as the 8-ray index

/// cos and sin of 2 pi m k / kDirectionBins for the key's harmonics.
struct Harmonics
{
  float cos_[kProfileHarmonics][kDirectionBins];
  float sin_[kProfileHarmonics][kDirectionBins];
  Harmonics()
  {
    for (int m = 0; m < kProfileHarmonics; ++m)
      for (int k = 0; k < kDirectionBins; ++k)
      {
        const double a = 2.0 * M_PI * (m + 1) * k / kDirectionBins;
        cos_[m][k] = static_cast<float>(std::cos(a));
        sin_[m][k] = static_cast<float>(std::sin(a));
      }
  }
};

const Harmonics& harmonics()
{
  static const Harmonics h;
  return h;
}
}  // namespace

bool makeProfile(const float distance[kDirectionBins], RadialProfile& out)
{
  constexpr int n = kDirectionBins;
  int missing = 0;
  std::array<bool, kDirectionBins> have{};
  for (int k = 0; k < n; ++k)
  {
    if (!(distance[k] > 0.f))
    {
      ++missing;
      continue;
    }
    if (distance[k] < kShortestRay)
      return false;
    have[k] = true;
    out.centred[k] = std::log(distance[k]);
  }
  if (missing > kMaxMissingProfileRays)
    return false;
  // A missing ray: linear in the log between the nearest rays on either side.
  for (int k = 0; k < n && missing > 0; ++k)
  {
    if (have[k])
      continue;
    int before = 1, after = 1;
    while (!have[(k - before + n) % n])
      ++before;
    while (!have[(k + after) % n])
      ++after;
    const float a = out.centred[(k - before + n) % n], b = out.centred[(k + after) % n];
    out.centred[k] = a + (b - a) * static_cast<float>(before) / static_cast<float>(before + after);
  }
  float sum = 0.f;
  for (int k = 0; k < n; ++k)
    sum += out.centred[k];
  out.log_mean = sum / n;
  for (int k = 0; k < n; ++k)
    out.centred[k] -= out.log_mean;
  return true;
}

bool scanProfile(const RadialScanner& scanner, float x, float y, float theta, RadialProfile& out)
{
  float distance[kDirectionBins];
  for (int k = 0; k < kDirectionBins; ++k)
  {
    const RayHit hit = scanner.scanAngle(x, y, theta + k * kBinAngle);
    distance[k] = hit.valid ? std::max(hit.distance, 1e-3f) : 0.f;
  }
  return makeProfile(distance, out);
}

bool tableProfile(const Prototype& prototype, int x, int y, RadialProfile& out)
{
  const std::uint8_t* raw = prototype.rawDistances(x, y);
  float distance[kDirectionBins];
  for (int k = 0; k < kDirectionBins; ++k)
    distance[k] = raw[k] == Prototype::kNoEdge ? 0.f : std::max(raw[k] * Prototype::kDistanceUnit, 1e-3f);
  return makeProfile(distance, out);
}

ProfileKey profileKey(const RadialProfile& profile)
{
  const Harmonics& h = harmonics();
  ProfileKey key;
  for (int m = 0; m < kProfileHarmonics; ++m)
  {
    float re = 0.f, im = 0.f;
    for (int k = 0; k < kDirectionBins; ++k)
    {
      re += profile.centred[k] * h.cos_[m][k];
      im += profile.centred[k] * h.sin_[m][k];
    }
    key[m] = std::sqrt(re * re + im * im) / kDirectionBins;
  }
  return key;
}

int alignProfiles(const RadialProfile& image, const RadialProfile& table, float& error)
{
  constexpr int n = kDirectionBins;
  // The table twice over: every shift is one contiguous run.
  float twice[2 * n];
  std::copy(table.centred.begin(), table.centred.end(), twice);
  std::copy(table.centred.begin(), table.centred.end(), twice + n);
  int best = 0;
  float least = 0.f;
  for (int b = 0; b < n; ++b)
  {
    float sum = 0.f;
    for (int k = 0; k < n; ++k)
    {
      const float d = image.centred[k] - twice[b + k];
      sum += d * d;
    }
    if (b == 0 || sum < least)
    {
      least = sum;
      best = b;
    }
  }
  error = least / n;
  return best;
}

ProfileIndex::ProfileIndex(const PrototypeMemory& memory, int stride, const std::vector<bool>& active)
{
  if (stride < 1)
    throw ParameterError("the profile index's stride must be at least 1 table px, got " + std::to_string(stride));
  const std::vector<int> indexed = indexedPrototypes(memory.size(), active);
  // Each prototype's places on OpenCV's threads (parallel_for.h), merged in prototype order.
  std::vector<std::vector<Entry>> parts(indexed.size());
  std::vector<std::vector<ProfileKey>> part_keys(indexed.size());
  parallelFor(static_cast<int>(indexed.size()), resolveThreads(0), [&](int i) {
    const Prototype& prototype = memory[indexed[i]];
    for (int at_stride = stride; at_stride >= 1; at_stride = at_stride == 1 ? 0 : std::max(1, at_stride / 2))
    {
      parts[i].clear();
      part_keys[i].clear();
      for (const cv::Point& at : prototype.interior())
      {
        RadialProfile profile;
        if (at.x % at_stride != 0 || at.y % at_stride != 0 || !tableProfile(prototype, at.x, at.y, profile))
          continue;
        parts[i].push_back({indexed[i], static_cast<short>(at.x), static_cast<short>(at.y)});
        part_keys[i].push_back(profileKey(profile));
      }
      if (static_cast<int>(parts[i].size()) >= kMinPlacesPerPrototype)
        break;
    }
  });
  std::size_t total = 0;
  for (std::size_t i = 0; i < parts.size(); ++i)
  {
    if (static_cast<int>(parts[i].size()) < kMinPlacesPerPrototype)
      left_out_.push_back(memory[indexed[i]].label());
    else
      total += parts[i].size();
  }
  if (total == 0)
    throw MemoryError("the profile index has no usable entry: no prototype has " +
                      std::to_string(kMinPlacesPerPrototype) + " pixels that see an edge in all but " +
                      std::to_string(kMaxMissingProfileRays) + " of the " + std::to_string(kDirectionBins) +
                      " directions within the table's reach");
  entries_.reserve(total);
  keys_.create(static_cast<int>(total), kProfileHarmonics, CV_32F);
  int row = 0;
  for (std::size_t i = 0; i < parts.size(); ++i)
  {
    if (static_cast<int>(parts[i].size()) < kMinPlacesPerPrototype)
      continue;
    entries_.insert(entries_.end(), parts[i].begin(), parts[i].end());
    for (const ProfileKey& key : part_keys[i])
      std::copy(key.begin(), key.end(), keys_.ptr<float>(row++));
  }
  cv::flann::IndexParams tree;
  tree.setAlgorithm(cvflann::FLANN_INDEX_KDTREE_SINGLE);
  tree.setInt("leaf_max_size", kLeafSize);
  tree.setBool("reorder", true);
  tree_ = std::make_unique<cv::flann::Index>(keys_, tree);
}

ProfileIndex::~ProfileIndex() = default;

std::vector<ProposalCandidate> ProfileIndex::query(const PrototypeMemory& memory, const RadialProfile& profile,
                                                   int search, int keep) const
{
  if (search < 1 || keep < 1 || entries_.empty())
    return {};
  search = std::min<int>(search, static_cast<int>(entries_.size()));
  const ProfileKey key = profileKey(profile);
  std::vector<float> q(key.begin(), key.end());
  std::vector<int> indices(search, -1);
  std::vector<float> dists(search, 0.f);
  tree_->knnSearch(q, indices, dists, search, cv::flann::SearchParams());
  std::vector<ProposalCandidate> out;
  out.reserve(search);
  for (int i : indices)
  {
    if (i < 0 || i >= static_cast<int>(entries_.size()))
      continue;  // FLANN pads a short answer with -1
    const Entry& e = entries_[i];
    RadialProfile table;
    if (e.prototype >= static_cast<int>(memory.size()) || !tableProfile(memory[e.prototype], e.x, e.y, table))
      continue;
    ProposalCandidate c;
    c.prototype = e.prototype;
    c.x = e.x;
    c.y = e.y;
    float error = 0.f;
    c.bin = alignProfiles(profile, table, error);
    c.log_scale = table.log_mean - profile.log_mean;
    c.distance = std::sqrt(error);
    out.push_back(c);
  }
  const std::size_t kept = std::min<std::size_t>(static_cast<std::size_t>(keep), out.size());
  std::partial_sort(out.begin(), out.begin() + kept, out.end(),
                    [](const ProposalCandidate& a, const ProposalCandidate& b) { return a.distance < b.distance; });
  out.resize(kept);
  return out;
}
}  // namespace amcr
