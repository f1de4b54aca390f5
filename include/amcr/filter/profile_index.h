// The radial-profile index (the feature feedback of the paper's section 4.3,
// which it left as future work): a V-particle whose M-particles have not
// converged reads its whole radial profile, the log distance to the first
// edge in all 72 directions the tables hold, at the cost of one scan. Minus
// its mean the profile is free of scale (the scale goes into the mean); the
// magnitudes of its Fourier series are free of rotation, and make the key:
// one key per prototype place instead of one per place and heading. The
// heading then comes from aligning the profile with the candidate's (the
// circular shift with the least squared difference), which also ranks the
// candidates far better than the key alone: on the benchmark's `paper`
// frames the true place is the best of 64 for 36% of the points on a target
// (the 8-ray index: 18%), within the best 8 for 49% (35%; bench/index_rank.cpp).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/scan/radial_scan.h"
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
/// Fourier harmonics (1..kProfileHarmonics) of a profile that make its key.
constexpr int kProfileHarmonics = 12;
/// Rays of a profile that may miss an edge (filled from their neighbours).
constexpr int kMaxMissingProfileRays = 8;

/// A place's radial profile: log distances in kDirectionBins directions
/// minus their mean (bin k at the heading plus k bins), and the mean.
struct RadialProfile
{
  std::array<float, kDirectionBins> centred{};
  float log_mean = 0.f;
};

using ProfileKey = std::array<float, kProfileHarmonics>;

/// The profile of `distance` (kDirectionBins distances, px; <= 0 where a ray
/// met no edge): false when more than kMaxMissingProfileRays rays miss or a
/// ray is shorter than 2 px (a place on an edge sees it everywhere). A
/// missing ray takes the log distance interpolated between its neighbours.
bool makeProfile(const float distance[kDirectionBins], RadialProfile& out);

/// The profile a scanner shows from (x, y) with bin 0 at heading `theta` (rad).
bool scanProfile(const RadialScanner& scanner, float x, float y, float theta, RadialProfile& out);

/// The profile a prototype's table holds at pixel (x, y), bin 0 at table angle 0.
bool tableProfile(const Prototype& prototype, int x, int y, RadialProfile& out);

/// The magnitudes of harmonics 1..kProfileHarmonics of the centred profile:
/// unchanged by a rotation by whole bins.
ProfileKey profileKey(const RadialProfile& profile);

/// The table bin b at which `image` (bin 0 at the V-particle's heading) fits
/// `table` best: least sum over k of (image[k] - table[(b + k) mod 72])^2,
/// returned in `error` (per bin, log units squared).
int alignProfiles(const RadialProfile& image, const RadialProfile& table, float& error);

class ProfileIndex
{
public:
  /// Fewest places a prototype needs to be indexed.
  static constexpr int kMinPlacesPerPrototype = 10;

  /// Indexes every prototype of `memory` whose `active` flag is set (all
  /// when `active` is empty) at pixels `stride` table px apart (every pixel
  /// of a prototype with too few places at that stride); a prototype with
  /// too few places even then is left out (leftOut()). Throws ParameterError
  /// for a stride below 1, MemoryError when nothing is indexed.
  ProfileIndex(const PrototypeMemory& memory, int stride, const std::vector<bool>& active = {});
  ~ProfileIndex();
  ProfileIndex(const ProfileIndex&) = delete;
  ProfileIndex& operator=(const ProfileIndex&) = delete;

  /// The `keep` best aligned of the `search` places whose keys are nearest
  /// to the profile's (k-d tree), best first: heading bin from the
  /// alignment, log_scale from the profiles' means, distance the root of the
  /// alignment error per bin. `memory` is the memory indexed (its tables
  /// give the candidates' profiles).
  std::vector<ProposalCandidate> query(const PrototypeMemory& memory, const RadialProfile& profile, int search,
                                       int keep) const;

  std::size_t size() const { return entries_.size(); }
  const std::vector<std::string>& leftOut() const { return left_out_; }

private:
  struct Entry
  {
    int prototype;
    short x, y;
  };
  std::vector<Entry> entries_;
  cv::Mat keys_;  // one row per entry, CV_32F
  std::unique_ptr<cv::flann::Index> tree_;
  std::vector<std::string> left_out_;
};
}  // namespace amcr
