// drawOverlay: a fixed size per input size and memory, every input type the
// library takes, the input kept 1:1 at the top left, and clear errors.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/overlay.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"

namespace
{
cv::Mat silhouette(int kind)
{
  cv::Mat image(120, 120, CV_8UC1, cv::Scalar(255));
  if (kind == 0)
    cv::circle(image, cv::Point(60, 60), 40, cv::Scalar(0), cv::FILLED);
  else if (kind == 1)
    cv::rectangle(image, cv::Rect(20, 40, 80, 40), cv::Scalar(0), cv::FILLED);
  else
    cv::fillConvexPoly(image, std::vector<cv::Point>{{60, 10}, {110, 110}, {10, 110}}, cv::Scalar(0));
  return image;
}

amcr::Params smallParams()
{
  amcr::Params params;
  params.num_v_particles = 8;
  params.m_particles_per_prototype = 10;
  params.prototype_size = 48;
  return params;
}

cv::Mat scene()
{
  cv::Mat image(150, 201, CV_8UC3, cv::Scalar(200, 190, 180));
  cv::circle(image, cv::Point(70, 70), 35, cv::Scalar(20, 20, 20), cv::FILLED);
  cv::rectangle(image, cv::Rect(120, 30, 60, 30), cv::Scalar(30, 30, 30), cv::FILLED);
  return image;
}

/// A recognizer of one disc prototype that has seen scene(), and an object
/// of that prototype to draw (no outline yet).
struct DiscView
{
  amcr::Recognizer recognizer{smallParams(), [] {
                                auto memory = std::make_shared<amcr::PrototypeMemory>();
                                memory->add("disc", silhouette(0), smallParams());
                                return memory;
                              }()};
  cv::Mat bgr = scene();
  amcr::RecognizedObject object;

  DiscView()
  {
    recognizer.step(bgr);
    object.label = "disc";
    object.prototype_id = 0;
    object.track_id = 3;
    object.score = 0.9;
    object.support = 4;
  }
};
}  // namespace

TEST(OverlayLayout, CellsFitBesideTheImageAndTheSizeIsEven)
{
  for (const cv::Size input : {cv::Size(640, 480), cv::Size(201, 150), cv::Size(64, 40), cv::Size(1280, 721)})
    for (const std::size_t r : {1u, 3u, 17u, 100u})
    {
      const amcr::OverlayLayout layout = amcr::overlayLayout(input, r);
      const std::string what = std::to_string(input.width) + "x" + std::to_string(input.height) + ", " +
                               std::to_string(r) + " prototypes";
      EXPECT_EQ(layout.size.width % 2, 0) << what;
      EXPECT_EQ(layout.size.height % 2, 0) << what;
      EXPECT_EQ(layout.image, cv::Rect(cv::Point(0, 0), input)) << what;
      EXPECT_GE(layout.cell, amcr::OverlayOptions().min_panel_size) << what;
      EXPECT_GE(layout.grid_columns * layout.grid_rows, static_cast<int>(r)) << what;
      const cv::Rect whole(cv::Point(0, 0), layout.size);
      for (std::size_t k = 0; k < r; ++k)
      {
        const cv::Rect cell = layout.cellRect(static_cast<int>(k));
        EXPECT_EQ(cell & whole, cell) << what << ", cell " << k;
        EXPECT_TRUE((cell & layout.image).empty()) << what << ", cell " << k;
      }
      // The same arguments, the same layout.
      EXPECT_EQ(amcr::overlayLayout(input, r).size, layout.size);
    }
}

TEST(DrawOverlay, FixedSizeBgrForEveryInputType)
{
  const amcr::Params params = smallParams();
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (int k = 0; k < 3; ++k)
    memory->add("shape-" + std::to_string(k), silhouette(k), params);
  amcr::Recognizer recognizer(params, memory);
  const cv::Mat bgr = scene();
  const cv::Size expected = amcr::overlayLayout(bgr.size(), memory->size()).size;

  cv::Mat gray, bgra, gray16, bgr32f;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  gray.convertTo(gray16, CV_16U, 257.0);
  bgr.convertTo(bgr32f, CV_32F, 1.0 / 255.0);
  for (const cv::Mat& input : {bgr, gray, bgra, gray16, bgr32f})
    for (int step = 0; step < 3; ++step)
    {
      const amcr::RecognitionResult result = recognizer.step(input);
      const cv::Mat overlay = amcr::drawOverlay(input, recognizer, result);
      ASSERT_EQ(overlay.type(), CV_8UC3) << "input type " << input.type();
      ASSERT_EQ(overlay.size(), expected) << "input type " << input.type();
    }

  // Without the status line and the particles, the input is copied 1:1.
  amcr::OverlayOptions plain;
  plain.draw_status = false;
  plain.draw_m_particles = false;
  plain.draw_v_particles = false;
  amcr::RecognitionResult nothing;
  const cv::Mat overlay = amcr::drawOverlay(bgr, recognizer, nothing, plain);
  cv::Mat difference;
  cv::absdiff(overlay(cv::Rect(cv::Point(0, 0), bgr.size())), bgr, difference);
  EXPECT_EQ(cv::countNonZero(difference.reshape(1)), 0);

  // The M-particles show in the prototype panels.
  amcr::OverlayOptions with_m = plain;
  with_m.draw_m_particles = true;
  const cv::Rect column = amcr::overlayLayout(bgr.size(), memory->size()).column;
  cv::absdiff(amcr::drawOverlay(bgr, recognizer, nothing, with_m)(column), overlay(column), difference);
  EXPECT_GT(cv::countNonZero(difference.reshape(1)), 0);
}

TEST(DrawOverlay, DrawsRecognizedObjectsEvenWithOddValues)
{
  DiscView view;
  amcr::Recognizer& recognizer = view.recognizer;
  const cv::Mat& bgr = view.bgr;
  amcr::RecognitionResult result;
  amcr::RecognizedObject object = view.object;
  for (int k = 0; k < 16; ++k)
    object.outline.emplace_back(70 + 35 * std::cos(k * CV_PI / 8), 70 + 35 * std::sin(k * CV_PI / 8));
  object.outline.emplace_back(std::nan(""), 1.0);  // skipped, not drawn
  object.correspondences.push_back({cv::Point2d(70, 70), cv::Point2d(60, 60)});
  object.correspondences.push_back({cv::Point2d(1e9, -1e9), cv::Point2d(-5, 500)});  // far outside: clipped
  result.objects.push_back(object);
  amcr::RecognizedObject unknown = object;
  unknown.prototype_id = 7;  // not in the memory: outline only
  result.objects.push_back(unknown);

  const cv::Mat overlay = amcr::drawOverlay(bgr, recognizer, result);
  EXPECT_EQ(overlay.size(), amcr::overlayLayout(bgr.size(), 1).size);
  // The outline changed the input where it runs.
  const cv::Vec3b on_outline = overlay.at<cv::Vec3b>(70, 105);
  EXPECT_NE(on_outline, bgr.at<cv::Vec3b>(70, 105));
}

// A V-particle deciding between look-alike clusters: the outline of each
// interpretation is drawn in its prototype's colour where that
// interpretation puts it, with a white ring when its move was chosen to
// decide; a V-particle with no competing clusters draws neither.
TEST(DrawOverlay, ShowsTheClustersADiscriminatingVParticleDecidesBetween)
{
  const amcr::Params params = smallParams();
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("disc", silhouette(0), params);
  memory->add("bar", silhouette(1), params);
  const cv::Mat grey(150, 201, CV_8UC1, cv::Scalar(128));
  amcr::VParticleView v;
  v.position = cv::Point2f(100, 75);
  v.discriminating = true;
  // The disc's table centred on (60, 75), the bar's on (140, 75), both 1:1.
  const cv::Point2d disc_centre = (*memory)[0].centre(), bar_centre = (*memory)[1].centre();
  v.competing.push_back({0, cv::Matx23d(1, 0, 60 - disc_centre.x, 0, 1, 75 - disc_centre.y), 0.5f});
  v.competing.push_back({1, cv::Matx23d(1, 0, 140 - bar_centre.x, 0, 1, 75 - bar_centre.y), 0.3f});
  amcr::OverlayOptions options;
  options.draw_status = false;
  const cv::Rect image_area = amcr::overlayLayout(grey.size(), memory->size(), options).image;
  const auto drawnWith = [&](const amcr::VParticleView& particle) {
    amcr::FilterView one;
    one.v.push_back(particle);
    return amcr::drawOverlay(grey, *memory, one, amcr::RecognitionResult(), options)(image_area).clone();
  };
  const auto countIn = [](const cv::Mat& picture, const cv::Scalar& colour, const cv::Rect& where) {
    cv::Mat mask;
    cv::inRange(picture(where), colour - cv::Scalar(40, 40, 40), colour + cv::Scalar(40, 40, 40), mask);
    return cv::countNonZero(mask);
  };
  const cv::Mat drawn = drawnWith(v);
  EXPECT_GT(countIn(drawn, amcr::prototypeColour(0), cv::Rect(20, 30, 80, 90)), 20) << "the disc's outline about (60, 75)";
  EXPECT_GT(countIn(drawn, amcr::prototypeColour(1), cv::Rect(100, 50, 90, 50)), 20) << "the bar's outline about (140, 75)";
  EXPECT_GT(countIn(drawn, cv::Scalar(255, 255, 255), cv::Rect(92, 67, 17, 17)), 4) << "the white ring";

  amcr::VParticleView undecided = v;  // deciding, but its move came from the exploration policy
  undecided.discriminating = false;
  const cv::Mat no_ring = drawnWith(undecided);
  EXPECT_GT(countIn(no_ring, amcr::prototypeColour(1), cv::Rect(100, 50, 90, 50)), 20);
  EXPECT_EQ(countIn(no_ring, cv::Scalar(255, 255, 255), cv::Rect(92, 67, 17, 17)), 0);
  amcr::VParticleView exploring = undecided;
  exploring.competing.clear();
  EXPECT_EQ(countIn(drawnWith(exploring), amcr::prototypeColour(1), cv::Rect(100, 50, 90, 50)), 0)
      << "a V-particle with no competing clusters draws no outline";
}

// The label shows the viewing angle and the anisotropy, and says when the homography is used.
TEST(DrawOverlay, LabelShowsTheViewingAngleAndAnisotropy)
{
  amcr::RecognizedObject object;
  object.label = "target";
  object.track_id = 2;
  object.score = 0.87;
  object.support = 9;
  object.anisotropy = 2.0;
  object.viewing_angle_deg = 60.0;
  std::vector<std::string> lines = amcr::objectLabel(object);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "target #2 0.87 (9) tentative");
  EXPECT_EQ(lines[1], "view 60deg 2.00:1");
  object.homography_valid = true;
  object.anisotropy = 3.0;
  object.viewing_angle_deg = 70.53;
  lines = amcr::objectLabel(object);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1], "view 71deg 3.00:1 persp");
  object.visible_share = 0.634;  // partly covered: said how much shows
  EXPECT_EQ(amcr::objectLabel(object)[0], "target #2 0.87 (9) tentative vis 63%");
}

// The covered part of an outline is drawn in grey over the outline's
// colour, the visible part in the track's colour.
TEST(DrawOverlay, ShowsTheCoveredPartOfAnOutline)
{
  DiscView view;
  amcr::Recognizer& recognizer = view.recognizer;
  const cv::Mat& bgr = view.bgr;
  amcr::RecognitionResult result;
  amcr::RecognizedObject object = view.object;
  object.visible_share = 0.75;
  // A square outline (10 points a side), its right side covered.
  for (int k = 0; k < 10; ++k)
    object.outline.emplace_back(40 + 6 * k, 40);
  for (int k = 0; k < 10; ++k)
    object.outline.emplace_back(100, 40 + 6 * k);
  for (int k = 0; k < 10; ++k)
    object.outline.emplace_back(100 - 6 * k, 100);
  for (int k = 0; k < 10; ++k)
    object.outline.emplace_back(40, 100 - 6 * k);
  object.covered.assign(object.outline.size(), 0);
  for (int k = 10; k < 20; ++k)
    object.covered[k] = 1;
  result.objects.push_back(object);
  const cv::Mat overlay = amcr::drawOverlay(bgr, recognizer, result);
  result.objects[0].covered.clear();
  const cv::Mat uncovered = amcr::drawOverlay(bgr, recognizer, result);
  // Against the same outline with nothing covered: the covered side changed
  // (grey dashes), the other three sides did not.
  int changed_covered = 0, changed_visible = 0;
  for (int t = 45; t < 95; ++t)
  {
    const auto changed = [&](int y, int x) { return overlay.at<cv::Vec3b>(y, x) != uncovered.at<cv::Vec3b>(y, x); };
    changed_covered += changed(t, 100);
    changed_visible += changed(t, 40) + changed(40, t) + changed(100, t);
  }
  EXPECT_GT(changed_covered, 10) << "the covered side is not drawn apart";
  EXPECT_EQ(changed_visible, 0) << "a visible side was drawn as covered";
  for (int t = 45; t < 95; ++t)
  {
    const cv::Vec3b c = overlay.at<cv::Vec3b>(t, 100);
    if (c != uncovered.at<cv::Vec3b>(t, 100))
    {
      EXPECT_TRUE(c[0] == c[1] && c[1] == c[2]) << "the covered side's dashes are not grey at y " << t;
    }
  }
}

TEST(DrawOverlay, RefusesEmptyAndUnsupportedImages)
{
  const amcr::Params params = smallParams();
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  memory->add("disc", silhouette(0), params);
  amcr::Recognizer recognizer(params, memory);
  const amcr::RecognitionResult nothing;
  EXPECT_THROW(amcr::drawOverlay(cv::Mat(), recognizer, nothing), amcr::InputError);
  EXPECT_THROW(amcr::drawOverlay(cv::Mat(10, 10, CV_8UC2, cv::Scalar(0)), recognizer, nothing), amcr::InputError);
  EXPECT_THROW(amcr::drawOverlay(cv::Mat(10, 10, CV_32SC1, cv::Scalar(0)), recognizer, nothing), amcr::InputError);
}

// The view the overlay draws from: every V-particle once, every M-particle
// once in its prototype's list with a valid owner, dominant prototypes only
// where the cluster converged, and flow trails only after a flow.
TEST(FilterView, HoldsEveryParticleOnce)
{
  amcr::Params params = smallParams();
  params.optical_flow = true;
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (int k = 0; k < 3; ++k)
    memory->add("shape-" + std::to_string(k), silhouette(k), params);
  amcr::Recognizer recognizer(params, memory);
  recognizer.step(scene());
  amcr::FilterView view = recognizer.view();
  ASSERT_EQ(view.v.size(), recognizer.vParticles().size());
  for (const amcr::VParticleView& v : view.v)
  {
    EXPECT_FALSE(v.trail.valid) << "a trail before any flow";
    EXPECT_GE(v.dominant_prototype, -1);
    EXPECT_LT(v.dominant_prototype, 3);
  }
  ASSERT_EQ(view.m_by_prototype.size(), memory->size());
  std::size_t dots = 0;
  for (const auto& prototype : view.m_by_prototype)
    for (const amcr::MParticleDot& dot : prototype)
    {
      EXPECT_GE(dot.v, 0);
      EXPECT_LT(dot.v, static_cast<int>(view.v.size()));
      ++dots;
    }
  std::size_t held = 0;  // KLD-sampling: a V-particle holds a range of its slots
  for (const amcr::MRange& r : recognizer.filter().mRanges())
    held += r.size();
  EXPECT_EQ(dots, held);

  recognizer.step(scene());  // the same frame again: the flow is zero and found
  view = recognizer.view();
  int trails = 0;
  for (const amcr::VParticleView& v : view.v)
    trails += v.trail.valid ? 1 : 0;
  EXPECT_GT(trails, 0) << "no V-particle shows where the flow took it from";
}
