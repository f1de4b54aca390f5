#include "shape_context.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/affine.h"
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
    const std::vector<cv::Point> outline = prototypeOutline(p.mask);
    Model model{p.label, resampleOutline(outline, config.points), outline.empty() ? 0.0 : cv::contourArea(outline)};
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
    const std::vector<cv::Point2f> points = resampleOutline(c->contour, config_.points);
    if (points.empty() || c->area <= 0)
      continue;
    // The candidate's nearest prototype, over all starting orientations, with a plausible pose.
    double best = std::numeric_limits<double>::infinity();
    Detection detection;
    for (const Model& model : models_)
    {
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
          pose.label = model.label;
          pose.score = -d;
          detection = std::move(pose);
        }
      }
    }
    if (best <= config_.max_distance)
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
