// The homography fit on the image (include/amcr/extraction/homography_fit.h,
// perspective_choice.h): a drawn target (dark square, light disc, four light
// dots) under known perspective views of a tilted plane (a sweep of tilts,
// perspective strengths and rotations) over clutter, the fit started, as the
// extractor does, from the affine refined on the edges from the best affine
// approximation of the view, slightly perturbed. The fitted homography must
// map the target square's corners within kCornerTolerance (1.5 px) of the
// truth, the model selection must take it where the best affine is more than
// 3 px off at a corner, and keep the affine for views that are affine (the
// target and every drawn silhouette, anisotropy 1-3).
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/extraction/homography_fit.h"
#include "amcr/extraction/outline_fit.h"
#include "amcr/extraction/perspective_choice.h"
#include "scene_drawing.h"

namespace
{
using amcr::Homography;
using amcr_test::ShapeId;

// The drawn target (like the printed target of visp's mire-2 sequence): a
// dark square, a big light disc in its middle and four light dots, in
// prototype px of a kPrototypeImageSize image. The square's corners are
// the corners the test holds the fit to.
const std::vector<cv::Point2d> kTargetSquare = {{20, 20}, {179, 20}, {179, 179}, {20, 179}};

struct Disc
{
  cv::Point2d centre;
  double radius;
};
const std::vector<Disc> kTargetDiscs = {
    {{99.5, 99.5}, 38}, {{50, 50}, 12}, {{149, 50}, 12}, {{149, 149}, 12}, {{50, 149}, 12}};

std::vector<cv::Point2d> discPolygon(const Disc& d)
{
  std::vector<cv::Point2d> out;
  for (int k = 0; k < 180; ++k)
    out.emplace_back(d.centre.x + d.radius * std::cos(k * M_PI / 90), d.centre.y + d.radius * std::sin(k * M_PI / 90));
  return out;
}

constexpr double kCornerTolerance = 1.5;   // px, largest corner error of the fitted homography
constexpr double kAffineCannotExplain = 3.0;  // px: a best affine this far off at a corner needs the homography
constexpr double kVerifyTolerance = 2.0;   // px, the object's score tolerance (candidate_fit.cpp)

/// A view of the prototype as a planar target: the prototype image's centre
/// at distance `distance` (in focal lengths' units: focal = 1) on the optical
/// axis, the plane tilted by `tilt` about its x axis, turned by `rotation`
/// about the optical axis, and `scale` image px per prototype px at the
/// centre; the image centre at (320, 240). Smaller `focal` px: stronger perspective.
Homography planarView(double tilt_deg, double rotation_deg, double focal, double scale)
{
  const double t = tilt_deg * M_PI / 180.0, r = rotation_deg * M_PI / 180.0;
  const cv::Matx33d rz(std::cos(r), -std::sin(r), 0, std::sin(r), std::cos(r), 0, 0, 0, 1);
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t));
  const cv::Matx33d rot = rz * rx;
  const double depth = 1.0;                      // the centre's depth
  const double metres_per_px = scale * depth / focal;  // so that the centre maps with `scale`
  const cv::Point2d c = amcr_test::prototypeCentre();
  // Prototype px -> plane coordinates -> camera [r1 r2 t] -> pixels.
  const cv::Matx33d to_plane(metres_per_px, 0, -metres_per_px * c.x, 0, metres_per_px, -metres_per_px * c.y, 0, 0, 1);
  const cv::Matx33d extrinsic(rot(0, 0), rot(0, 1), 0, rot(1, 0), rot(1, 1), 0, rot(2, 0), rot(2, 1), depth);
  const cv::Matx33d k(focal, 0, 320, 0, focal, 240, 0, 0, 1);
  Homography h = k * extrinsic * to_plane;
  amcr::normalizeHomography(h, h);
  return h;
}

std::vector<cv::Point2d> mapped(const Homography& h, const std::vector<cv::Point2d>& points)
{
  std::vector<cv::Point2d> out;
  for (const auto& p : points)
    out.push_back(amcr::applyHomography(h, p));
  return out;
}

/// The target drawn into `image` under `view` (prototype px -> image px).
void drawTarget(cv::Mat& image, const Homography& view, double dark, double light)
{
  amcr_test::fillPolygon(image, mapped(view, kTargetSquare), dark);
  for (const Disc& d : kTargetDiscs)
    amcr_test::fillPolygon(image, mapped(view, discPolygon(d)), light);
}

std::shared_ptr<const amcr::PrototypeMemory> targetMemory(const amcr::Params& params)
{
  cv::Mat image(amcr_test::kPrototypeImageSize, amcr_test::kPrototypeImageSize, CV_8UC1, cv::Scalar(255));
  drawTarget(image, amcr::liftAffine(amcr::identityAffine()), 0, 255);
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("target", image, params);
  return memory;
}

/// Largest distance between `corners` (prototype px) mapped by `a` and by `b`.
double cornerError(const Homography& a, const Homography& b, const std::vector<cv::Point2d>& corners = kTargetSquare)
{
  double worst = 0.0;
  for (const cv::Point2d& c : corners)
  {
    const cv::Point2d d = amcr::applyHomography(a, c) - amcr::applyHomography(b, c);
    worst = std::max(worst, std::isfinite(d.x) && std::isfinite(d.y) ? std::hypot(d.x, d.y) : 1e9);
  }
  return worst;
}

/// The least-squares affine of the view over the target square's outline (prototype px -> image px).
amcr::Affine bestAffine(const Homography& h)
{
  std::vector<cv::Point2d> from;
  for (std::size_t i = 0; i < kTargetSquare.size(); ++i)
    for (int k = 0; k < 40; ++k)
      from.push_back(kTargetSquare[i] + (kTargetSquare[(i + 1) % kTargetSquare.size()] - kTargetSquare[i]) * (k / 40.0));
  amcr::Affine a;
  EXPECT_TRUE(amcr::fitAffine(from, mapped(h, from), a));
  return a;
}

/// A background with clutter (lines, other shapes, a gradient) that keeps
/// away from where `approximation` puts a prototype image's shape.
cv::Mat clutter(ShapeId keep_out_of, const amcr::Affine& approximation, std::uint64_t seed)
{
  amcr_test::Scene scene;
  scene.objects = {{keep_out_of, approximation, 35.0}};
  scene.clutter.seed = seed;
  scene.clutter.keep_out = 40.0;
  return amcr_test::renderBackground(scene);
}

/// The target under `view` over clutter, with noise.
cv::Mat drawTargetView(const Homography& view, const amcr::Affine& approximation, std::uint64_t seed)
{
  cv::Mat image = clutter(ShapeId::kFlag, approximation, seed);
  drawTarget(image, view, 30.0, 215.0);
  return amcr_test::addNoise(image, 6.0, seed);
}

/// A silhouette under an affine view over clutter, with noise.
cv::Mat drawShapeView(ShapeId shape, const amcr::Affine& view, std::uint64_t seed)
{
  cv::Mat image = clutter(shape, view, seed);
  amcr_test::fillPolygon(image, amcr_test::transformPoints(view, amcr_test::shapePolygon(shape)), 35.0);
  return amcr_test::addNoise(image, 6.0, seed);
}

/// What the extractor does for one object: the affine refined from `start`
/// (prototype px -> image px), then the model selection; the answer is
/// returned in prototype px -> image px.
struct Outcome
{
  amcr::PerspectiveFit fit;
  Homography fitted;  // the fitted homography, prototype px -> image px
  Homography answer;  // the chosen model, prototype px -> image px
};

Outcome fitFrom(const cv::Mat& image, const amcr::Prototype& prototype, const amcr::Affine& start,
                const amcr::Params& params)
{
  const cv::Mat scan = amcr::prepareScanImage(image, params.blur_sigma);
  const amcr::RadialScanner scanner(scan, params.edge_threshold, params.max_ray_length);
  const amcr::Affine table_start = amcr::composeAffine(prototype.tableToOriginal(), start);
  const amcr::Affine affine =
      amcr::refineOnEdges(prototype, scanner, table_start, params.refine_iterations, params.refine_search);
  const double support = amcr::outlineSupport(prototype, scanner, affine, kVerifyTolerance);
  amcr::PerspectiveRule rule;
  rule.max_scale = params.max_affine_scale;
  Outcome out;
  out.fit = amcr::choosePerspective(prototype, scanner, affine, support, params.refine_iterations,
                                    params.refine_search, rule);
  const Homography original_to_table = amcr::liftAffine(prototype.originalToTable());
  out.fitted = amcr::composeHomography(original_to_table, out.fit.homography);
  out.answer = amcr::composeHomography(original_to_table, out.fit.table_to_image);
  return out;
}

/// The best affine turned by 1.5 degrees about the shape's centre and moved by (1.5, -1) px.
amcr::Affine perturbed(const amcr::Affine& a)
{
  const cv::Point2d c = amcr::applyAffine(a, amcr_test::prototypeCentre());
  const double r = 0.5 * M_PI / 180.0;
  const amcr::Affine turn(std::cos(r), -std::sin(r), c.x - std::cos(r) * c.x + std::sin(r) * c.y + 1.0, std::sin(r),
                          std::cos(r), c.y - std::sin(r) * c.x - std::cos(r) * c.y - 0.5);
  return amcr::composeAffine(a, turn);
}

struct View
{
  double tilt_deg;
  double rotation_deg;
  double focal;  // px; the target spans about 190 px, so 500 is a strong perspective, 2000 a weak one
};

std::string describe(const View& v)
{
  std::ostringstream out;
  out << "tilt " << v.tilt_deg << " deg, rotation " << v.rotation_deg << " deg, focal " << v.focal << " px";
  return out.str();
}

// The sweep: tilts 20-60 degrees (anisotropy 1.06-2) x perspective from weak
// to strong x three rotations, 45 views; each start is the best affine
// approximation of the view, turned by 0.5 degrees and moved by (1, -0.5) px.
TEST(HomographyFit, PerspectiveSweepMapsTheCornersWithinTolerance)
{
  const amcr::Params params;
  const auto memory = targetMemory(params);
  int demanded = 0, used = 0;
  std::uint64_t seed = 1;
  for (double tilt : {20.0, 35.0, 45.0, 55.0, 60.0})
    for (double focal : {500.0, 900.0, 2000.0})
      for (double rotation : {0.0, 30.0, -70.0})
      {
        const View v{tilt, rotation, focal};
        const Homography truth = planarView(v.tilt_deg, v.rotation_deg, v.focal, 1.2);
        const amcr::Affine approximation = bestAffine(truth);
        const cv::Mat image = drawTargetView(truth, approximation, seed++);
        const Outcome out = fitFrom(image, (*memory)[0], perturbed(approximation), params);
        const double affine_error = cornerError(amcr::liftAffine(approximation), truth);
        if (!out.fit.tried)
        {
          // Not tried: the affine was already on the edges, and must be right.
          EXPECT_LE(cornerError(out.answer, truth), kCornerTolerance) << describe(v) << ": the affine answer";
          continue;
        }
        EXPECT_LE(cornerError(out.fitted, truth), kCornerTolerance)
            << describe(v) << ": fitted homography; the best affine is " << affine_error << " px off";
        if (affine_error > kAffineCannotExplain)
        {
          ++demanded;
          EXPECT_TRUE(out.fit.used) << describe(v) << ": the best affine is " << affine_error
                                    << " px off, residual affine " << out.fit.affine_residual << " homography "
                                    << out.fit.homography_residual;
        }
        if (out.fit.used)
        {
          ++used;
          EXPECT_LE(cornerError(out.answer, truth), kCornerTolerance) << describe(v);
          EXPECT_GE(out.fit.support, out.fit.affine_support) << describe(v);
        }
      }
  // The sweep must hold views the affine cannot explain, or the selection is not tested.
  EXPECT_GE(demanded, 15);
  EXPECT_GE(used, demanded);
}

// Affine views (anisotropy 1-3, rotated and sheared): the homography may fit
// them as well, but the rule keeps the affine.
TEST(HomographyFit, AnAffineViewKeepsTheAffine)
{
  const amcr::Params params;
  std::uint64_t seed = 100;
  const auto target = targetMemory(params);
  for (double anisotropy : {1.0, 2.0, 3.0})
    for (double rotation : {0.6, -1.9})
    {
      const amcr::Affine truth =
          amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, rotation, 1.4, 1.4 / anisotropy, 0.2);
      const cv::Mat image = drawTargetView(amcr::liftAffine(truth), truth, seed++);
      const Outcome out = fitFrom(image, (*target)[0], perturbed(truth), params);
      EXPECT_FALSE(out.fit.used) << "target, anisotropy " << anisotropy << ", rotation " << rotation
                                 << ": residual affine " << out.fit.affine_residual << " homography "
                                 << out.fit.homography_residual;
      EXPECT_LE(cornerError(out.answer, amcr::liftAffine(truth)), kCornerTolerance)
          << "target, anisotropy " << anisotropy << ", rotation " << rotation;
    }
  for (ShapeId shape : amcr_test::allShapes())
  {
    const auto memory = amcr_test::drawnMemory({shape}, params);
    for (double anisotropy : {1.0, 2.0, 3.0})
    {
      const amcr::Affine truth =
          amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.6, 1.5, 1.5 / anisotropy, 0.2);
      const cv::Mat image = drawShapeView(shape, truth, seed++);
      const Outcome out = fitFrom(image, (*memory)[0], perturbed(truth), params);
      EXPECT_FALSE(out.fit.used) << amcr_test::shapeName(shape) << ", anisotropy " << anisotropy << ": residual affine "
                                 << out.fit.affine_residual << " homography " << out.fit.homography_residual;
    }
  }
}

TEST(HomographyFit, WellConditionedRefusesMirrorsCollapseAndStrongPerspective)
{
  const std::vector<cv::Point2d> box = {{0, 0}, {100, 0}, {100, 80}, {0, 80}};
  std::string why;
  EXPECT_TRUE(amcr::homographyWellConditioned(amcr::liftAffine(amcr::Affine(1.2, 0.1, 5, -0.1, 0.9, 7)), box, 8, 2, &why))
      << why;
  EXPECT_FALSE(amcr::homographyWellConditioned(amcr::liftAffine(amcr::Affine(-1, 0, 0, 0, 1, 0)), box, 8, 2, &why));
  EXPECT_NE(why.find("mirror"), std::string::npos) << why;
  EXPECT_FALSE(amcr::homographyWellConditioned(amcr::liftAffine(amcr::Affine(1, 0, 0, 0, 0.01, 0)), box, 8, 2, &why));
  EXPECT_NE(why.find("scale"), std::string::npos) << why;
  // The far side 3x deeper than the near one: w runs from 1 to 3 over the box.
  EXPECT_FALSE(amcr::homographyWellConditioned(Homography(1, 0, 0, 0, 1, 0, 0.02, 0, 1), box, 100, 2, &why));
  EXPECT_NE(why.find("perspective"), std::string::npos) << why;
  // The horizon crosses the box.
  EXPECT_FALSE(amcr::homographyWellConditioned(Homography(1, 0, 0, 0, 1, 0, -0.02, 0, 1), box, 8, 100, &why));
  EXPECT_NE(why.find("horizon"), std::string::npos) << why;
  // A moderate perspective is fine.
  EXPECT_TRUE(amcr::homographyWellConditioned(Homography(1, 0, 0, 0, 1, 0, 0.004, 0.002, 1), box, 8, 2, &why)) << why;
}

TEST(HomographyFit, LiftComposeAndApplyAgreeWithTheAffine)
{
  const amcr::Affine a(1.3, -0.4, 12, 0.5, 0.8, -3), b(0.7, 0.1, 40, -0.2, 1.1, 5);
  const Homography h = amcr::composeHomography(amcr::liftAffine(a), amcr::liftAffine(b));
  for (const cv::Point2d& p : {cv::Point2d(0, 0), cv::Point2d(17.5, -3), cv::Point2d(200, 150)})
  {
    const cv::Point2d e = amcr::applyAffine(amcr::composeAffine(a, b), p), g = amcr::applyHomography(h, p);
    EXPECT_NEAR(g.x, e.x, 1e-9);
    EXPECT_NEAR(g.y, e.y, 1e-9);
  }
  // Behind the camera: no point.
  const cv::Point2d behind = amcr::applyHomography(Homography(1, 0, 0, 0, 1, 0, -1, 0, 1), {2, 0});
  EXPECT_TRUE(std::isnan(behind.x) && std::isnan(behind.y));
}
}  // namespace
