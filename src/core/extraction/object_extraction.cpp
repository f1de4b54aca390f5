#include "amcr/extraction/object_extraction.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/calib3d.hpp>

namespace amcr
{
namespace
{
constexpr int kMeanShiftPasses = 5;           // most mean-shift steps of a cluster's centre
constexpr float kMeanShiftSettled = 0.05f;    // table px: a step shorter than this ends the mean shift

// estimateAffine2D of a group's correspondences (RANSAC; the threshold is
// params.group_tolerance, input px).
constexpr std::size_t kRansacMaxIterations = 2000;
constexpr double kRansacConfidence = 0.99;
constexpr std::size_t kRansacRefineIterations = 10;  // Levenberg-Marquardt steps on the inliers

/// Mean shift over the M-particles [begin, end) of prototype k, from `centre`,
/// with a disc of squared radius `r2` (table px^2); `members` gets the count
/// in the last disc.
cv::Point2f meanShift(const MParticleSet& m, std::size_t begin, std::size_t end, int k, cv::Point2f centre, float r2,
                      int& members)
{
  members = 0;
  for (int pass = 0; pass < kMeanShiftPasses; ++pass)
  {
    cv::Point2f sum(0, 0);
    members = 0;
    for (std::size_t i = begin; i < end; ++i)
    {
      if (m.prototype[i] != k)
        continue;
      const float dx = m.x[i] - centre.x, dy = m.y[i] - centre.y;
      if (dx * dx + dy * dy <= r2)
      {
        sum += cv::Point2f(m.x[i], m.y[i]);
        ++members;
      }
    }
    if (members == 0)
      break;
    const cv::Point2f next = sum / static_cast<float>(members);
    const bool settled = std::hypot(next.x - centre.x, next.y - centre.y) < kMeanShiftSettled;
    centre = next;
    if (settled)
      break;
  }
  return centre;
}

/// The mean A of prototype k's M-particles with a fitted A within the disc of
/// squared radius r2 about `centre`; false when there is none.
bool meanAffine(const MParticleSet& m, std::size_t begin, std::size_t end, int k, cv::Point2f centre, float r2,
                Affine& mean)
{
  double a[6] = {0, 0, 0, 0, 0, 0};
  int with_affine = 0;
  for (std::size_t i = begin; i < end; ++i)
  {
    const float dx = m.x[i] - centre.x, dy = m.y[i] - centre.y;
    if (m.prototype[i] != k || dx * dx + dy * dy > r2 || m.affine_valid[i] != kFittedAffine)
      continue;
    for (int j = 0; j < 6; ++j)
      a[j] += m.affine[j][i];
    ++with_affine;
  }
  if (with_affine == 0)
    return false;
  mean = Affine(a[0], a[1], a[2], a[3], a[4], a[5]) * (1.0 / with_affine);
  return true;
}
}  // namespace

VParticleCluster dominantCluster(const MParticleSet& m, std::size_t begin, std::size_t end, int prototype_count,
                                 double radius, bool with_likeliest)
{
  VParticleCluster cluster;
  if (end <= begin || prototype_count <= 0)
    return cluster;
  std::vector<int> counts(prototype_count, 0);
  std::vector<std::size_t> most_likely(prototype_count, end);
  for (std::size_t i = begin; i < end; ++i)
  {
    const int k = m.prototype[i];
    ++counts[k];
    if (most_likely[k] == end || m.log_likelihood[i] > m.log_likelihood[most_likely[k]])
      most_likely[k] = i;
  }
  std::vector<int> order;
  for (int k = 0; k < prototype_count; ++k)
    if (counts[k] > 0)
      order.push_back(k);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return counts[a] > counts[b]; });

  // The densest mode: a mean shift from the most likely particle of each
  // prototype, most populated first, until no prototype holds more particles
  // than the densest mode found (a prototype that holds the most particles
  // spread over the table loses to a tight cluster in another).
  const float r2 = static_cast<float>(radius * radius);
  int k = -1, members = 0;
  cv::Point2f centre;
  for (const int candidate : order)
  {
    if (counts[candidate] <= members)
      break;
    int candidate_members = 0;
    const std::size_t start = most_likely[candidate];
    const cv::Point2f candidate_centre =
        meanShift(m, begin, end, candidate, cv::Point2f(m.x[start], m.y[start]), r2, candidate_members);
    if (k < 0 || candidate_members > members)
    {
      k = candidate;
      members = candidate_members;
      centre = candidate_centre;
    }
  }
  cluster.prototype = k;
  cluster.mean = centre;
  cluster.share = static_cast<float>(members) / static_cast<float>(end - begin);
  cluster.has_affine = meanAffine(m, begin, end, k, centre, r2, cluster.image_to_table);
  // The mode about the single most likely M-particle (its prototype's best):
  // with a likelihood that hardly tells prototypes apart, the truth is often
  // the most likely hypothesis long before its mode is the densest.
  int top = -1;
  for (int candidate = 0; with_likeliest && candidate < prototype_count; ++candidate)
    if (most_likely[candidate] != end &&
        (top < 0 || m.log_likelihood[most_likely[candidate]] > m.log_likelihood[most_likely[top]]))
      top = candidate;
  if (top >= 0 && m.affine_valid[most_likely[top]] == kFittedAffine)
  {
    const std::size_t start = most_likely[top];
    int top_members = 0;
    LikeliestMode& mode = cluster.likeliest;
    mode.prototype = top;
    mode.log_likelihood = m.log_likelihood[start];
    mode.mean = meanShift(m, begin, end, top, cv::Point2f(m.x[start], m.y[start]), r2, top_members);
    mode.has_affine = meanAffine(m, begin, end, top, mode.mean, r2, mode.image_to_table);
  }
  return cluster;
}

std::vector<VParticleCluster> dominantClusters(const std::vector<VParticle>& v, const MParticleSet& m,
                                               const std::vector<MRange>& ranges, int prototype_count,
                                               const ExtractionParams& params)
{
  std::vector<VParticleCluster> clusters(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    clusters[i] = dominantCluster(m, ranges[i].begin, ranges[i].end, prototype_count, params.cluster_radius,
                                  params.likeliest_fits > 0);
    clusters[i].v = static_cast<int>(i);
    clusters[i].converged = clusters[i].share >= params.cluster_min_share;
  }
  return clusters;
}

namespace
{
/// Whether the points spread in two directions enough to fix an affine.
bool wellSpread(const std::vector<cv::Point2f>& points, double min_extent)
{
  if (points.size() < 3)
    return false;
  cv::Point2d mean(0, 0);
  for (const auto& p : points)
    mean += cv::Point2d(p);
  mean *= 1.0 / points.size();
  double sxx = 0, syy = 0, sxy = 0;
  for (const auto& p : points)
  {
    const double dx = p.x - mean.x, dy = p.y - mean.y;
    sxx += dx * dx;
    syy += dy * dy;
    sxy += dx * dy;
  }
  sxx /= points.size();
  syy /= points.size();
  sxy /= points.size();
  const double smallest = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  return smallest >= min_extent * min_extent;
}
}  // namespace

std::vector<ObjectHypothesis> groupClusters(const std::vector<VParticle>& v,
                                            const std::vector<VParticleCluster>& clusters,
                                            const ExtractionParams& params, int min_members)
{
  std::vector<int> order;
  for (std::size_t i = 0; i < clusters.size(); ++i)
    if (clusters[i].has_affine && clusters[i].converged)
      order.push_back(static_cast<int>(i));
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return clusters[a].share > clusters[b].share; });

  std::vector<bool> grouped(clusters.size(), false);
  std::vector<ObjectHypothesis> hypotheses;
  for (int seed : order)
  {
    if (grouped[seed])
      continue;
    Affine seed_to_image;
    if (!invertAffine(clusters[seed].image_to_table, seed_to_image))
      continue;
    ObjectHypothesis h;
    h.prototype = clusters[seed].prototype;
    for (int j : order)
    {
      if (grouped[j] || clusters[j].prototype != h.prototype)
        continue;
      const cv::Point2d mapped = applyAffine(seed_to_image, cv::Point2d(clusters[j].mean));
      const VParticle& vj = v[clusters[j].v];
      if (std::hypot(mapped.x - vj.x, mapped.y - vj.y) <= params.group_tolerance)
        h.members.push_back(j);
    }
    if (static_cast<int>(h.members.size()) < min_members)
      continue;
    for (int j : h.members)
      grouped[j] = true;

    // Fit to every correspondence when they spread enough (RANSAC drops the
    // odd one out); else keep the seed's own affine.
    std::vector<cv::Point2f> table_points, image_points;
    for (int j : h.members)
    {
      table_points.push_back(clusters[j].mean);
      image_points.emplace_back(v[clusters[j].v].x, v[clusters[j].v].y);
    }
    h.table_to_image = seed_to_image;
    if (wellSpread(table_points, 2.0 * params.cluster_radius))
    {
      const cv::Mat fitted = cv::estimateAffine2D(table_points, image_points, cv::noArray(), cv::RANSAC,
                                                  params.group_tolerance, kRansacMaxIterations, kRansacConfidence,
                                                  kRansacRefineIterations);
      if (!fitted.empty())
        h.table_to_image = Affine(fitted.ptr<double>(0)[0], fitted.ptr<double>(0)[1], fitted.ptr<double>(0)[2],
                                  fitted.ptr<double>(1)[0], fitted.ptr<double>(1)[1], fitted.ptr<double>(1)[2]);
    }
    hypotheses.push_back(std::move(h));
  }
  return hypotheses;
}
}  // namespace amcr
