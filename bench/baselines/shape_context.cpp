#include "shape_context.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/memory/edge_model.h"
#include "amcr/memory/prototype.h"
#include "amcr/scan/radial_scan.h"
#include "candidate_contours.h"

namespace amcr_bench
{
/// The extractor's transform algorithm: OpenCV's full affine transformer, which each iteration
/// warps the first point set toward the second, plus the point matches it was given last (the
/// extractor keeps its matches to itself and hands them only to its transform algorithm).
class ShapeContext::MatchRecorder : public cv::ShapeTransformer
{
public:
  void estimateTransformation(cv::InputArray transforming, cv::InputArray target,
                              std::vector<cv::DMatch>& matches) override
  {
    matches_ = matches;
    affine_->estimateTransformation(transforming, target, matches);
  }
  float applyTransformation(cv::InputArray input, cv::OutputArray output) override
  {
    return affine_->applyTransformation(input, output);
  }
  void warpImage(cv::InputArray image, cv::OutputArray output, int flags, int border_mode,
                 const cv::Scalar& border_value) const override
  {
    affine_->warpImage(image, output, flags, border_mode, border_value);
  }
  /// queryIdx into the first set, trainIdx into the second; indices past a set's end are the
  /// extractor's dummy points (a point left unmatched).
  const std::vector<cv::DMatch>& matches() const { return matches_; }

private:
  cv::Ptr<cv::AffineTransformer> affine_ = cv::createAffineTransformer(true);
  std::vector<cv::DMatch> matches_;
};

namespace
{
/// `count` points evenly spaced in arc length along the closed `contour`; empty when it has no length.
std::vector<cv::Point2f> resampleOutline(const std::vector<cv::Point>& contour, int count)
{
  const std::size_t n = contour.size();
  std::vector<double> along(n + 1, 0.0);  // arc length at each point; along[n] closes the loop
  for (std::size_t i = 0; i < n; ++i)
    along[i + 1] = along[i] + cv::norm(contour[(i + 1) % n] - contour[i]);
  std::vector<cv::Point2f> points;
  if (n == 0 || along[n] <= 0)
    return points;
  std::size_t edge = 0;
  for (int k = 0; k < count; ++k)
  {
    const double s = along[n] * k / count;
    while (along[edge + 1] <= s)
      ++edge;
    const double t = (s - along[edge]) / (along[edge + 1] - along[edge]);
    const cv::Point2d a = contour[edge], b = contour[(edge + 1) % n];
    points.emplace_back(a + t * (b - a));
  }
  return points;
}

/// `count` of `points` spread over them: the one nearest their centroid, then each time the one farthest
/// from those taken (farthest-point sampling); all of them when they are no more.
std::vector<cv::Point2f> spreadOver(const std::vector<cv::Point2f>& points, int count)
{
  if (static_cast<int>(points.size()) <= count)
    return points;
  cv::Point2f centroid(0, 0);
  for (const cv::Point2f& p : points)
    centroid += p / static_cast<float>(points.size());
  const auto squared = [](const cv::Point2f& d) { return d.x * d.x + d.y * d.y; };
  std::size_t next = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (squared(points[i] - centroid) < squared(points[next] - centroid))
      next = i;
  std::vector<float> gap(points.size(), std::numeric_limits<float>::infinity());  // to the nearest taken, squared
  std::vector<cv::Point2f> taken;
  while (static_cast<int>(taken.size()) < count)
  {
    taken.push_back(points[next]);
    std::size_t farthest = next;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      gap[i] = std::min(gap[i], squared(points[i] - taken.back()));
      if (gap[i] > gap[farthest])
        farthest = i;
    }
    next = farthest;
  }
  return taken;
}

/// A grey template's edge points as amcr reads them (amcr::Prototype with the default parameters, the
/// template's region as its alpha channel), original prototype px. Throws std::invalid_argument naming
/// the label when amcr cannot read it (too few edges).
std::vector<cv::Point2f> templateModelPoints(const PrototypeImage& p)
{
  cv::Mat image = p.grey;
  if (cv::countNonZero(p.mask) < static_cast<int>(p.mask.total()))
    cv::merge(std::vector<cv::Mat>{p.grey, p.grey, p.grey, p.mask}, image);
  const amcr::Params params;
  std::vector<cv::Point2f> points;
  try
  {
    // The edge model does not depend on the lookup table's stride: the coarsest is the quickest to build.
    const amcr::Prototype prototype(p.label, image, params.prototype_size, params.edge_threshold, params.blur_sigma,
                                    amcr::Prototype::kMaxTableStride, "", params.edge_full_strength);
    for (const amcr::OutlinePoint& o : prototype.outline())
      points.emplace_back(amcr::applyAffine(prototype.tableToOriginal(), cv::Point2d(o.position)));
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument("shape context baseline: " + std::string(e.what()));
  }
  return points;
}

/// The frame's edge points as a template's are found (amcr::templateEdgePoints with amcr's default
/// parameters and amcr::kMinTemplateChain, as amcr::Prototype reads a template), frame px.
std::vector<cv::Point2f> frameEdgePoints(const cv::Mat& grey)
{
  const amcr::Params params;
  std::vector<cv::Point2f> points;
  for (const amcr::OutlinePoint& o : amcr::templateEdgePoints(amcr::prepareScanImage(grey, params.blur_sigma),
                                                              params.edge_threshold, params.edge_full_strength,
                                                              amcr::kMinTemplateChain, cv::Mat()))
    points.push_back(o.position);
  return points;
}

/// The `points` inside the closed `contour` (bounding box `box`) or within 2 px of it.
std::vector<cv::Point2f> pointsWithin(const std::vector<cv::Point2f>& points, const std::vector<cv::Point>& contour,
                                      const cv::Rect& box)
{
  const cv::Rect around(box.x - 2, box.y - 2, box.width + 4, box.height + 4);
  cv::Mat inside = cv::Mat::zeros(around.size(), CV_8UC1);
  const std::vector<std::vector<cv::Point>> contours = {contour};
  cv::drawContours(inside, contours, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(), INT_MAX, -around.tl());
  cv::drawContours(inside, contours, 0, cv::Scalar(255), 5, cv::LINE_8, cv::noArray(), INT_MAX, -around.tl());
  std::vector<cv::Point2f> within;
  for (const cv::Point2f& p : points)
  {
    const cv::Point at(cvRound(p.x) - around.x, cvRound(p.y) - around.y);
    if (at.inside(cv::Rect(0, 0, around.width, around.height)) && inside.at<unsigned char>(at))
      within.push_back(p);
  }
  return within;
}

/// `points` turned by `angle` (rad) and scaled by `scale` about the origin.
std::vector<cv::Point2f> turned(const std::vector<cv::Point2f>& points, double angle, double scale)
{
  const double c = scale * std::cos(angle), s = scale * std::sin(angle);
  std::vector<cv::Point2f> out;
  out.reserve(points.size());
  for (const cv::Point2f& p : points)
    out.emplace_back(static_cast<float>(c * p.x - s * p.y), static_cast<float>(s * p.x + c * p.y));
  return out;
}

/// The prototype -> image affine fitted (RANSAC) to the extractor's matches between `prototype`
/// and `image` points, and its inlier pairs as the correspondences; false when the matches fix no
/// affine or it is no print's pose: mirrored, stretched beyond the configured anisotropy, or
/// scaling the prototype's area by other than `area_ratio` (the candidate's area over the
/// prototype's), give or take the configured change.
bool fitPose(const std::vector<cv::Point2f>& prototype, const std::vector<cv::Point2f>& image,
             const std::vector<cv::DMatch>& matches, const ShapeContextConfig& config, double area_ratio,
             Detection& out)
{
  std::vector<cv::Point2f> from, to;
  for (const cv::DMatch& m : matches)
    if (m.queryIdx < static_cast<int>(prototype.size()) && m.trainIdx < static_cast<int>(image.size()))
    {
      from.push_back(prototype[m.queryIdx]);
      to.push_back(image[m.trainIdx]);
    }
  if (from.size() < 3)
    return false;
  std::vector<unsigned char> inlier;
  const cv::Mat affine = cv::estimateAffine2D(from, to, inlier, cv::RANSAC, config.ransac_px);
  if (affine.empty())
    return false;
  out.prototype_to_image = cv::Matx23d(affine);
  double smallest, largest;
  amcr::affineScales(out.prototype_to_image, smallest, largest);
  const cv::Matx23d& a = out.prototype_to_image;
  const double det = a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0);
  if (det <= 0 || largest > config.max_anisotropy * smallest || det > config.max_area_change * area_ratio ||
      det * config.max_area_change < area_ratio)
    return false;
  for (std::size_t k = 0; k < from.size(); ++k)
    if (inlier[k])
      out.correspondences.push_back({cv::Point2d(to[k]), cv::Point2d(from[k])});
  return true;
}
}  // namespace

ShapeContext::ShapeContext(const std::vector<PrototypeImage>& prototypes, const ShapeContextConfig& config)
  : config_(config), recorder_(cv::makePtr<MatchRecorder>())
{
  for (const PrototypeImage& p : prototypes)
  {
    Model model;
    if (p.isTemplate())
    {
      const std::vector<cv::Point2f> edges = templateModelPoints(p);
      std::vector<cv::Point2f> hull;
      cv::convexHull(edges, hull);
      model = {p.label, spreadOver(edges, config.template_points), hull.size() < 3 ? 0.0 : cv::contourArea(hull), true};
    }
    else
    {
      const std::vector<cv::Point> outline = prototypeOutline(p.mask);
      model = {p.label, resampleOutline(outline, config.points), outline.empty() ? 0.0 : cv::contourArea(outline)};
    }
    if (model.points.empty() || model.area <= 0)
      throw std::invalid_argument("shape context baseline: prototype '" + p.label + "' holds no shape (mask > 127)");
    models_.push_back(std::move(model));
  }
  extractor_ = cv::createShapeContextDistanceExtractor();
  // Not OpenCV's rotation-invariant descriptor: it puts the relative angles that fall outside
  // (0, 2 pi] into its first bin or drops them, so it still depends on the orientation, and being
  // invariant it cannot tell a wrong turn of the alignment. From one start, the star of the tests
  // came out turned by about 144 degrees in 7 of 12 clean poses; the plain descriptor from 8
  // starting orientations (`turns`) found all 12, and tells clutter apart better than the
  // invariant one from 8 starts (drawn scenes: clutter at distances from 0.15 against 0.11).
  extractor_->setRotationInvariant(false);
  extractor_->setIterations(config.iterations);
  // The affine transformer's "bending energy" is the log ratio of each step's singular values: it
  // would penalise the anisotropic poses the frames show. fitPose() rejects implausible ones instead.
  extractor_->setBendingEnergyWeight(0.0f);
  extractor_->setTransformAlgorithm(recorder_);
}

std::vector<Detection> ShapeContext::detect(const cv::Mat& grey)
{
  if (grey.empty() || models_.empty())
    return {};
  cv::Mat edges;
  cv::Canny(grey, edges, config_.canny_low, config_.canny_high);
  cv::dilate(edges, edges, cv::Mat());  // a contour runs along boundary pixels, up to 1 px off the edge
  const bool any_template =
      std::any_of(models_.begin(), models_.end(), [](const Model& m) { return m.inner_edges; });
  const std::vector<cv::Point2f> edge_points = any_template ? frameEdgePoints(grey) : std::vector<cv::Point2f>();
  struct Candidate
  {
    std::vector<cv::Point> contour;
    cv::Rect box;
    double area;
  };
  std::vector<Candidate> candidates;
  for (auto& contour : candidateContours(grey, config_.adaptive_block, config_.adaptive_c, config_.clean_px))
  {
    const cv::Rect box = cv::boundingRect(contour);
    const int longer = std::max(box.width, box.height);
    if (longer < config_.min_size || longer > config_.max_size)
      continue;
    // An outline lies on edges; the adaptive threshold's halo around a shape of the other polarity does not.
    int on_edge = 0;
    for (const cv::Point& p : contour)
      on_edge += edges.at<unsigned char>(p) != 0;
    if (on_edge < config_.min_edge_share * contour.size())
      continue;
    const double area = cv::contourArea(contour);
    candidates.push_back({std::move(contour), box, area});
  }
  // Clutter can give many: the largest are the likeliest prints, the smallest the likeliest noise.
  // Each outline is found by several binarisations: one of them is enough.
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.area > b.area; });
  std::vector<const Candidate*> kept;
  for (const Candidate& c : candidates)
  {
    if (static_cast<int>(kept.size()) >= config_.max_candidates)
      break;
    if (std::none_of(kept.begin(), kept.end(), [&](const Candidate* k) {
          return (k->box & c.box).area() >= config_.same_box * (k->box | c.box).area();
        }))
      kept.push_back(&c);
  }

  std::vector<Detection> found;
  for (const Candidate* c : kept)
  {
    const std::vector<cv::Point2f> outline = resampleOutline(c->contour, config_.points);
    if (outline.empty() || c->area <= 0)
      continue;
    // The edges within, for the grey templates.
    const std::vector<cv::Point2f> inner =
        any_template ? spreadOver(pointsWithin(edge_points, c->contour, c->box), config_.template_points)
                     : std::vector<cv::Point2f>();
    // The candidate's nearest prototype, over all starting orientations, with a plausible pose.
    double best = std::numeric_limits<double>::infinity(), limit = 0;
    Detection detection;
    for (const Model& model : models_)
    {
      const std::vector<cv::Point2f>& points = model.inner_edges ? inner : outline;
      if (points.size() < 3)
        continue;
      // The extractor normalises both sets by the first set's mean point distance: the prototype is
      // brought to the candidate's size first, or the first iteration compares mismatched scales.
      const double area_ratio = c->area / model.area;
      for (int t = 0; t < config_.turns; ++t)
      {
        const std::vector<cv::Point2f> start =
            turned(model.points, 2 * CV_PI * t / config_.turns, std::sqrt(area_ratio));
        double d;
        try
        {
          d = extractor_->computeDistance(start, points);
        }
        catch (const cv::Exception&)
        {
          continue;  // a degenerate candidate (e.g. all points on a line)
        }
        // The extractor warps a copy of `start` but keeps its order: the match indices are the
        // outline's, so the fit maps original prototype px to image px.
        Detection pose;
        if (d < best && fitPose(model.points, points, recorder_->matches(), config_, area_ratio, pose))
        {
          best = d;
          limit = model.inner_edges ? config_.template_max_distance : config_.max_distance;
          pose.label = model.label;
          pose.score = -d;
          detection = std::move(pose);
        }
      }
    }
    if (best <= limit)
      found.push_back(std::move(detection));
  }
  // One report per label: its best candidate.
  std::sort(found.begin(), found.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
  std::vector<Detection> best_per_label;
  for (Detection& d : found)
    if (std::none_of(best_per_label.begin(), best_per_label.end(),
                     [&](const Detection& kept) { return kept.label == d.label; }))
      best_per_label.push_back(std::move(d));
  return best_per_label;
}
}  // namespace amcr_bench
