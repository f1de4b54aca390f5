// Test inputs drawn in code (style point 9): prototype silhouettes, scenes
// that show them under a known affine over clutter, and the corner error
// that the end-to-end tests measure. Everything random takes an explicit
// seed, so a scene is the same on every machine and every run.
#pragma once

#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/base/affine.h"
#include "amcr/base/params.h"
#include "amcr/filter/particles.h"
#include "amcr/memory/prototype_memory.h"

namespace amcr_test
{
/// The silhouettes. None has a mirror or rotational symmetry, so the affine
/// between a silhouette and its image is unique.
enum class ShapeId
{
  kArrow,     ///< an arrow with uneven barbs and a notched tail
  kCrescent,  ///< an ellipse minus an off-axis disc, uneven horns
  kStar,      ///< an irregular five-pointed star
  kEll,       ///< an "L" with uneven arms and a chamfered top
  kFlag,      ///< a pole with a triangular pennant
};

/// Every shape, in enum order.
const std::vector<ShapeId>& allShapes();

/// "arrow", "crescent", ...: the label a test gives the shape's prototype.
std::string shapeName(ShapeId id);

/// For gtest's parameter printing.
inline void PrintTo(ShapeId id, std::ostream* os) { *os << shapeName(id); }

/// Side of a prototype image, px.
constexpr int kPrototypeImageSize = 200;

/// The shape's outline, a simple polygon in prototype-image px (OpenCV
/// pixel-centre convention: pixel (i, j) is centred on (i, j)).
std::vector<cv::Point2d> shapePolygon(ShapeId id);

/// A memory of the drawn prototypes of `shapes`, labelled by shapeName().
std::shared_ptr<const amcr::PrototypeMemory> drawnMemory(const std::vector<ShapeId>& shapes,
                                                         const amcr::Params& params = amcr::Params());

/// The drawn arrow, crescent and star, and the apple (drawApple(true),
/// labelled "apple"), with the default parameters; built once.
std::shared_ptr<const amcr::PrototypeMemory> memoryWithApple();

/// The 8 feature rays a prototype's table holds at pixel (x, y) for heading
/// bin `bin`, times `scale` (0 where a ray meets no edge): what a V-particle
/// would measure at that place of an image of the prototype `scale` times larger.
amcr::RaySignature tableRays(const amcr::Prototype& prototype, int x, int y, int bin, float scale);

/// A further silhouette for larger memories: a random spiky polygon of
/// 12-18 vertices drawn from `seed` (unlike the ShapeId shapes and the
/// clutter's random shapes), filled at 255 on 0, kPrototypeImageSize square.
cv::Mat drawRandomSilhouette(std::uint64_t seed);

/// An oval of semi-axes a x b px about `centre` whose radius waves by
/// `wave` px five times round (0: the oval itself), 720 vertices: a
/// look-alike of the oval that follows its outline within `wave` px.
std::vector<cv::Point2d> wavyOval(cv::Point2d centre, double a, double b, double wave);

/// An apple as a prototype image (kPrototypeImageSize square, 255 on 0): a
/// round body of radius kAppleRadius about kAppleCentre and, with `stem`, a
/// stem of 8 x 40 px rising from its top (about 14 % of the outline, as
/// MPEG-7's apples); without it, the disc an apple's body is.
cv::Mat drawApple(bool stem);
const cv::Point2d kAppleCentre(100, 112);
constexpr double kAppleRadius = 60.0;
const cv::Point2d kAppleStemTip(100, 20);  ///< the middle of the stem's top

/// A bird in profile (prototype-image px), head to the right; with `crest`,
/// a crest of three more vertices rises from the top of its head to
/// kCrestTip: two look-alikes that differ in one part only.
std::vector<cv::Point2d> drawnBird(bool crest);
/// The crest's tip and the middle of the head's top it rises from.
const cv::Point2d kCrestTip(150, 22);
const cv::Point2d kCrestBase(150, 62);

/// The prototype image: kPrototypeImageSize x kPrototypeImageSize, CV_8UC1,
/// the filled shape at 255 on 0 (white_on_black) or 0 on 255. Antialiased
/// edges unless `antialiased` is false (then only 0 and 255 occur).
cv::Mat drawPrototype(ShapeId id, bool white_on_black = true, bool antialiased = true);

/// A prototype image of `polygon` (prototype-image px): kPrototypeImageSize
/// square, CV_8UC1, filled antialiased at 255 on 0.
cv::Mat drawSilhouette(const std::vector<cv::Point2d>& polygon);

/// Fills `polygon` (px of `image`, pixel-centre convention) with grey level
/// `value` into a CV_8UC1 image. Antialiased by 4x4 supersampling (exact
/// area coverage up to 1/16 px^2), or hard-edged.
void fillPolygon(cv::Mat& image, const std::vector<cv::Point2d>& polygon, double value, bool antialiased = true);

/// Maps each point by an affine.
std::vector<cv::Point2d> transformPoints(const amcr::Affine& a, const std::vector<cv::Point2d>& points);

/// A prototype -> image affine: x' = image_centre + R(rotation) * [1 shear; 0 1]
/// * diag(scale_x, scale_y) * (x - prototype_centre). Rotation in rad.
amcr::Affine makeAffine(const cv::Point2d& prototype_centre, const cv::Point2d& image_centre, double rotation,
                        double scale_x, double scale_y, double shear);

/// The centre of the prototype image, px.
cv::Point2d prototypeCentre();

/// One memory shape placed in a scene.
struct Placement
{
  ShapeId shape = ShapeId::kArrow;
  amcr::Affine prototype_to_image = amcr::identityAffine();  ///< prototype px -> image px
  double grey = 35.0;                                        ///< fill grey level (dark on light, like a print)
};

/// What surrounds the objects. All of it is drawn from `seed`.
struct Clutter
{
  int random_shapes = 7;  ///< random star-shaped polygons, ellipses and boxes (none in any memory)
  std::vector<ShapeId> silhouettes;  ///< extra silhouettes drawn as distractors, under a random affine
  int lines = 10;                    ///< random straight lines, 1-3 px thick
  double noise_sigma = 6.0;          ///< Gaussian pixel noise, grey levels (new per frame)
  double background = 195.0;         ///< mean background grey level
  double gradient = 60.0;            ///< background grey-level change across the image, in a random direction
  double keep_out = 25.0;            ///< distractor shapes stay this far (px) from the objects' bounding boxes
  std::uint64_t seed = 1;
};

/// The end-to-end scenes' distractors: the default clutter with the two
/// silhouettes their memories leave out (kEll, kFlag), drawn from `seed`.
Clutter distractorClutter(std::uint64_t seed);

struct Scene
{
  cv::Size size{640, 480};
  std::vector<Placement> objects;
  Clutter clutter;
};

/// The scene without noise: gradient background, distractor shapes and lines,
/// then the objects on top (so nothing occludes them). CV_8UC1.
cv::Mat renderClean(const Scene& scene);

/// The scene without its objects (the distractors still keep away from them).
cv::Mat renderBackground(const Scene& scene);

/// Draws `objects` over `image` (CV_8UC1).
void drawObjects(cv::Mat& image, const std::vector<Placement>& objects);

/// Adds Gaussian noise of `sigma` grey levels drawn from `seed` (saturated to 8 bit).
cv::Mat addNoise(const cv::Mat& clean, double sigma, std::uint64_t seed);

/// `frames` frames of a static scene, each with its own noise (seed = clutter.seed * 1000 + frame).
std::vector<cv::Mat> renderSequence(const Scene& scene, int frames);

/// A sequence in which the objects move over a fixed background: frame k
/// shows `objects_at(k)` over renderBackground(scene) (whose distractors keep
/// away from scene.objects only), with noise seeded clutter.seed * 1000 + k.
template <typename ObjectsAt>
std::vector<cv::Mat> renderMovingSequence(const Scene& scene, int frames, ObjectsAt objects_at)
{
  const cv::Mat background = renderBackground(scene);
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k)
  {
    cv::Mat clean = background.clone();
    drawObjects(clean, objects_at(k));
    out.push_back(addNoise(clean, scene.clutter.noise_sigma, scene.clutter.seed * 1000 + static_cast<std::uint64_t>(k)));
  }
  return out;
}

/// `frames` frames of `silhouette` (a prototype image, 255 on the shape)
/// printed 150 grey levels darker than the paper under `truth` over the
/// background and distractors of `clutter` (kept off the print's place),
/// each frame with its own noise (seed clutter.seed * 1000 + frame): a
/// printed shape that is none of the ShapeId silhouettes.
std::vector<cv::Mat> printedOverClutter(const cv::Mat& silhouette, const amcr::Affine& truth, const Clutter& clutter,
                                        int frames);

/// The four corners of a prototype image of `size` (pixel-centre convention):
/// (0,0), (w-1,0), (w-1,h-1), (0,h-1).
std::vector<cv::Point2d> imageCorners(const cv::Size& size);

/// Mean distance, px, between the corners of a prototype image of `prototype_size`
/// mapped by `reported` and by `truth` (both prototype px -> image px).
double cornerError(const amcr::Affine& reported, const amcr::Affine& truth,
                   const cv::Size& prototype_size = cv::Size(kPrototypeImageSize, kPrototypeImageSize));

/// A fresh directory under the system temp directory, removed with its
/// contents on destruction.
class TempDir
{
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::string& path() const { return path_; }
  /// path() + "/" + name
  std::string file(const std::string& name) const;

private:
  std::string path_;
};
}  // namespace amcr_test
