#include "amcr/extraction/pose_votes.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "amcr/filter/particles.h"
#include "amcr/scan/ray_directions.h"

namespace amcr
{
namespace
{
constexpr double kAgreeCentreShare = 0.1;  // of the pose's image size (the prototype's longer side)
constexpr double kAgreeCentreMin = 4.0;    // px
constexpr double kAgreeTurn = 15.0 * M_PI / 180.0;
constexpr double kAgreeLogScale = 0.14;    // about 15%

struct Vote
{
  int place;
  int prototype;
  Affine pose;
  cv::Point2d centre;  // the prototype's centre in the image
  double turn;
  double log_scale;    // log(image px per table px)
  float distance;
  double size;         // the prototype's longer side in the image, px
};

bool agree(const Vote& a, const Vote& b)
{
  if (a.prototype != b.prototype || std::abs(a.log_scale - b.log_scale) > kAgreeLogScale ||
      std::abs(wrapAngle(a.turn - b.turn)) > kAgreeTurn)
    return false;
  const double reach = std::max(kAgreeCentreMin, kAgreeCentreShare * a.size);
  return std::hypot(a.centre.x - b.centre.x, a.centre.y - b.centre.y) <= reach;
}
}  // namespace

Affine matchPose(const ProposalCandidate& c, const RayPlace& place)
{
  const double scale = std::exp(-static_cast<double>(c.log_scale));  // image px per table px
  const double turn = place.theta - binToAngle(c.bin);
  const double a = scale * std::cos(turn), b = scale * std::sin(turn);
  // image = place + scale R (table - match point)
  return Affine(a, -b, place.x - a * c.x + b * c.y, b, a, place.y - b * c.x - a * c.y);
}

std::vector<PoseVote> poolPoseVotes(const ProposalIndex& index, const PrototypeMemory& memory,
                                    const RadialScanner& scanner, const std::vector<RayPlace>& places,
                                    int per_place)
{
  std::vector<Vote> votes;
  std::vector<int> longer_side(memory.size(), 0);  // each prototype's region's longer side, table px (0: not yet)
  for (std::size_t i = 0; i < places.size(); ++i)
  {
    const RayPlace& place = places[i];
    RayHit hits[kFeatureRays];
    scanFeatureRays(scanner, place.x, place.y, place.theta, hits);
    for (const ProposalCandidate& c : index.query(raySignature(hits), per_place))
    {
      const Prototype& p = memory[c.prototype];
      Vote v{static_cast<int>(i), c.prototype, matchPose(c, place), {}, 0.0, -static_cast<double>(c.log_scale),
             c.distance, 0.0};
      v.centre = applyAffine(v.pose, p.centre());
      v.turn = place.theta - binToAngle(c.bin);
      if (longer_side[c.prototype] == 0)
      {
        const cv::Rect box = cv::boundingRect(p.mask());
        longer_side[c.prototype] = std::max(1, std::max(box.width, box.height));
      }
      v.size = std::exp(v.log_scale) * longer_side[c.prototype];
      votes.push_back(v);
    }
  }
  std::stable_sort(votes.begin(), votes.end(), [](const Vote& a, const Vote& b) { return a.distance < b.distance; });
  struct Pool
  {
    const Vote* seed;
    std::vector<int> places;
  };
  std::vector<Pool> pools;
  for (const Vote& v : votes)
  {
    Pool* joined = nullptr;
    for (Pool& pool : pools)
      if (agree(*pool.seed, v))
      {
        joined = &pool;
        break;
      }
    if (!joined)
    {
      pools.push_back({&v, {}});
      joined = &pools.back();
    }
    if (std::find(joined->places.begin(), joined->places.end(), v.place) == joined->places.end())
      joined->places.push_back(v.place);
  }
  std::vector<PoseVote> out;
  for (const Pool& pool : pools)
    out.push_back({pool.seed->prototype, pool.seed->pose, pool.places, pool.seed->distance});
  std::stable_sort(out.begin(), out.end(), [](const PoseVote& a, const PoseVote& b) {
    return a.places.size() != b.places.size() ? a.places.size() > b.places.size() : a.distance < b.distance;
  });
  return out;
}
}  // namespace amcr
