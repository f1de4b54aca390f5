#include "line2d.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/affine.h"

namespace amcr_bench
{
namespace
{
/// min_size .. max_size in geometric steps of at most size_step, both ends included.
std::vector<double> templateSizes(const Line2dConfig& c)
{
  const double range = c.max_size / c.min_size;
  const int steps =
      range > 1 && c.size_step > 1 ? static_cast<int>(std::ceil(std::log(range) / std::log(c.size_step) - 1e-9)) : 0;
  std::vector<double> sizes;
  for (int k = 0; k <= steps; ++k)
    sizes.push_back(c.min_size * std::pow(range, steps > 0 ? static_cast<double>(k) / steps : 0.0));
  return sizes;
}

/// The identity, and per level and axis the area-kept stretch R(phi) diag(sqrt k, 1/sqrt k) R(-phi). The levels'
/// ln k are 2/3 of ln max_anisotropy (one level), 2/5 and 4/5 (two), ...: the gap at the rim, which only the
/// outer level covers, is half of that between levels.
std::vector<cv::Matx22d> templateStretches(const Line2dConfig& c)
{
  std::vector<cv::Matx22d> stretches = {cv::Matx22d::eye()};
  if (c.max_anisotropy <= 1)
    return stretches;
  for (int level = 1; level <= c.anisotropy_levels; ++level)
  {
    const double k = std::pow(c.max_anisotropy, 2.0 * level / (2 * c.anisotropy_levels + 1));
    for (int axis = 0; axis < c.stretch_axes; ++axis)
    {
      const double phi = CV_PI * axis / c.stretch_axes;
      const cv::Matx22d r(std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi));
      stretches.push_back(r * cv::Matx22d(std::sqrt(k), 0, 0, 1 / std::sqrt(k)) * r.t());
    }
  }
  return stretches;
}

/// `grey` in `region` (CV_8UC1, non-zero where the template is), and elsewhere the grey of the nearest region
/// pixel: warped onto a canvas, the template shows no edge at its region's border.
cv::Mat extendedOverRegion(const cv::Mat& grey, const cv::Mat& region)
{
  if (cv::countNonZero(region) == static_cast<int>(region.total()))
    return grey;
  cv::Mat distance, nearest;  // nearest: each pixel's label, the label of its nearest region pixel
  cv::distanceTransform(region == 0, distance, nearest, cv::DIST_L2, 5, cv::DIST_LABEL_PIXEL);
  std::vector<unsigned char> grey_of_label(region.total() + 1, 0);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x)
      if (region.at<unsigned char>(y, x))
        grey_of_label[nearest.at<int>(y, x)] = grey.at<unsigned char>(y, x);
  cv::Mat extended(grey.size(), CV_8UC1);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x)
      extended.at<unsigned char>(y, x) = grey_of_label[nearest.at<int>(y, x)];
  return extended;
}

/// Linemod takes a template's features only on its mask's outer ring (the mask less its 3 x 3 erosion). This
/// mask is `region` in alternate 2 x 2 blocks: each of its pixels is on the ring, and stays so at half resolution
/// (linemod halves the mask by nearest neighbour), so that the features may lie anywhere in the region.
cv::Mat everywhereMask(const cv::Mat& region)
{
  cv::Mat mask = cv::Mat::zeros(region.size(), CV_8UC1);
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x)
      if (region.at<unsigned char>(y, x) && (((x >> 1) + (y >> 1)) & 1))
        mask.at<unsigned char>(y, x) = 255;
  return mask;
}

/// LINE-2D as cv::linemod::getDefaultLINE() makes it (T = 5 and 8 px at full and half resolution, 63
/// features), with the frame's gradient threshold of the configuration.
cv::Ptr<cv::linemod::Detector> makeDetector(const Line2dConfig& c)
{
  const cv::linemod::ColorGradient defaults;
  const std::vector<cv::Ptr<cv::linemod::Modality>> modalities = {
      cv::makePtr<cv::linemod::ColorGradient>(c.weak_threshold, defaults.num_features, defaults.strong_threshold)};
  return cv::makePtr<cv::linemod::Detector>(modalities, std::vector<int>{5, 8});
}
}  // namespace

Line2d::Line2d(const std::vector<PrototypeImage>& prototypes, const Line2dConfig& config)
  : config_(config), detector_(makeDetector(config))
{
  // Every pyramid level linearises its response maps in T x T cells, so the frame's sides must be multiples of
  // T << level (80 px for LINE-2D's T = {5, 8}), and linemod's SSE code takes the rows of every level to be
  // 16-byte aligned (else a general protection fault): the width also a multiple of 16 << level (160 px in all).
  // Its refinement, on all levels but the coarsest, searches +-8 cells around a candidate: in a frame smaller
  // than the template plus 16 cells, it shifts the window out of the frame and drops the features there.
  int refine_margin = 0;
  for (int l = 0; l < detector_->pyramidLevels(); ++l)
  {
    cell_.width = std::lcm(cell_.width, std::lcm(detector_->getT(l), 16) << l);
    cell_.height = std::lcm(cell_.height, detector_->getT(l) << l);
    if (l + 1 < detector_->pyramidLevels())
      refine_margin = std::max(refine_margin, (16 * detector_->getT(l)) << l);
  }

  for (const PrototypeImage& p : prototypes)
    if (p.mask.empty() || cv::countNonZero(p.mask > 127) == 0)
      throw std::invalid_argument("line2d: prototype '" + p.label +
                                  "' shows no silhouette or template region (no mask pixel above 127)");
  // Rendering and linemod's feature extraction take milliseconds per template: the prototypes are built in
  // parallel, each into a detector of its own (addTemplate changes the detector), then copied into one.
  const int n = static_cast<int>(prototypes.size());
  std::vector<cv::Ptr<cv::linemod::Detector>> parts(n);
  models_.resize(n);
  cv::parallel_for_(cv::Range(0, n), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i)
    {
      parts[i] = makeDetector(config);
      models_[i] = build(prototypes[i], std::to_string(i), *parts[i]);
    }
  });
  for (int i = 0; i < n; ++i)
  {
    if (models_[i].views.empty())
      throw std::invalid_argument("line2d: prototype '" + prototypes[i].label +
                                  "' gives no template (too few gradient features at every size)");
    const std::string class_id = std::to_string(i);
    for (int t = 0; t < static_cast<int>(models_[i].views.size()); ++t)
      detector_->addSyntheticTemplate(parts[i]->getTemplates(class_id, t), class_id);
    parts[i].release();  // at the peak, every template once and one prototype's twice
    for (const View& view : models_[i].views)
    {
      min_frame_.width = std::max(min_frame_.width, view.box.width + refine_margin);
      min_frame_.height = std::max(min_frame_.height, view.box.height + refine_margin);
    }
  }
}

Line2d::Model Line2d::build(const PrototypeImage& p, const std::string& class_id, cv::linemod::Detector& detector) const
{
  const cv::Mat silhouette = p.mask > 127;  // a grey template's region
  const cv::Moments moments = cv::moments(silhouette, true);
  Model model{p.label, {moments.m10 / moments.m00, moments.m01 / moments.m00}, {}};
  std::vector<cv::Point> points, hull;  // the hull bounds each rendering's extent
  cv::findNonZero(silhouette, points);
  cv::convexHull(points, hull);
  // A grey template is warped as it is, not printed: its grey carried past its region, which gives the mask.
  const cv::Mat source = p.isTemplate() ? extendedOverRegion(p.grey, silhouette) : p.mask;

  const int rotations = std::max(1, static_cast<int>(std::lround(360.0 / config_.rotation_step)));
  // Room around the silhouette: the dilated mask, and linemod's 7x7 smoothing at half resolution.
  const int margin = config_.mask_dilation + 8;
  const cv::Mat dilation = cv::getStructuringElement(
      cv::MORPH_ELLIPSE, cv::Size(2 * config_.mask_dilation + 1, 2 * config_.mask_dilation + 1));
  for (double size : templateSizes(config_))
  {
    // Resampled by area to the size first, so that the warps below only rotate and stretch (no aliasing).
    cv::Matx23d scaled_to_original, original_to_scaled;
    const int longer = static_cast<int>(std::lround(size));
    const cv::Mat scaled = normalisedPrototype(source, longer, 0, scaled_to_original);
    cv::Matx23d same_map;
    const cv::Mat scaled_region = p.isTemplate() ? normalisedPrototype(silhouette, longer, 0, same_map) : cv::Mat();
    amcr::invertAffine(scaled_to_original, original_to_scaled);
    std::vector<cv::Point2d> hull_scaled;
    cv::transform(std::vector<cv::Point2d>(hull.begin(), hull.end()), hull_scaled, original_to_scaled);

    for (const cv::Matx22d& stretch : templateStretches(config_))
      for (int r = 0; r < rotations; ++r)
      {
        const double a = 2 * CV_PI * r / rotations;
        const cv::Matx22d l = cv::Matx22d(std::cos(a), -std::sin(a), std::sin(a), std::cos(a)) * stretch;
        cv::Matx23d to_source(l(0, 0), l(0, 1), 0, l(1, 0), l(1, 1), 0);
        std::vector<cv::Point2d> extent;
        cv::transform(hull_scaled, extent, to_source);
        const cv::Mat xy = cv::Mat(extent).reshape(1);
        double x0, x1, y0, y1;
        cv::minMaxIdx(xy.col(0), &x0, &x1);
        cv::minMaxIdx(xy.col(1), &y0, &y1);
        to_source(0, 2) = margin - x0;
        to_source(1, 2) = margin - y0;
        const cv::Size canvas(static_cast<int>(std::ceil(x1 - x0)) + 2 * margin + 1,
                              static_cast<int>(std::ceil(y1 - y0)) + 2 * margin + 1);

        cv::Mat alpha, print, mask;
        if (p.isTemplate())
        {
          // Its edges, inner ones included, are the features: anywhere in its region.
          cv::warpAffine(scaled, print, to_source, canvas, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
          cv::warpAffine(scaled_region, alpha, to_source, canvas, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
          mask = everywhereMask(alpha > 127);
        }
        else
        {
          cv::warpAffine(scaled, alpha, to_source, canvas, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
          alpha.convertTo(print, CV_8U, (config_.ink - config_.paper) / 255.0, config_.paper);
          cv::GaussianBlur(print, print, cv::Size(), config_.print_blur);
          cv::dilate(alpha > 127, mask, dilation);
        }
        cv::cvtColor(print, print, cv::COLOR_GRAY2BGR);  // the colour-gradient modality wants 3 channels
        View view{amcr::composeAffine(original_to_scaled, to_source), {}, size};
        // -1: fewer gradient features on the mask's outline than linemod takes (63; 31 at half resolution).
        if (detector.addTemplate({print}, class_id, mask, &view.box) >= 0)
          model.views.push_back(view);
      }
  }
  return model;
}

std::vector<Detection> Line2d::detect(const cv::Mat& grey)
{
  if (grey.empty())
    return {};
  // Padded at the right and bottom only, so that frame coordinates stay; replicated, so no new edge appears.
  const auto padded = [](int side, int least, int cell) { return (std::max(side, least) + cell - 1) / cell * cell; };
  cv::Mat frame;
  cv::copyMakeBorder(grey, frame, 0, padded(grey.rows, min_frame_.height, cell_.height) - grey.rows, 0,
                     padded(grey.cols, min_frame_.width, cell_.width) - grey.cols, cv::BORDER_REPLICATE);
  cv::cvtColor(frame, frame, cv::COLOR_GRAY2BGR);
  std::vector<cv::linemod::Match> matches;
  detector_->match({frame}, config_.threshold, matches);  // best first

  std::vector<Detection> found;
  std::vector<std::pair<cv::Point2d, double>> kept;  // centre and size of each report
  for (const cv::linemod::Match& m : matches)
  {
    if (static_cast<int>(found.size()) >= config_.max_reports)
      break;
    const Model& model = models_[std::stoul(m.class_id)];
    const View& view = model.views[m.template_id];
    Detection d;
    // The match puts the template's bounding box at (x, y): a shift of the template's pixels.
    d.prototype_to_image = view.prototype_to_source;
    d.prototype_to_image(0, 2) += m.x - view.box.x;
    d.prototype_to_image(1, 2) += m.y - view.box.y;
    const cv::Point2d centre = amcr::applyAffine(d.prototype_to_image, model.centre);
    const bool near_better = std::any_of(kept.begin(), kept.end(), [&](const auto& k) {
      return cv::norm(centre - k.first) < config_.nms_share * std::min(view.size, k.second);
    });
    if (near_better)
      continue;
    kept.emplace_back(centre, view.size);
    d.label = model.label;
    d.score = m.similarity / 100.0;
    found.push_back(std::move(d));
  }
  return found;
}
}  // namespace amcr_bench
