// The one-more-prototype collapse (a grey template cut from a camera frame
// itself: found alone by half the recognizer seeds, by none with one more
// prototype in memory). A drawn scene like the real one: a dark square face
// with a ring of 12 light dots a little off its centre, over a cluttered
// background of grey blobs and bars, 384 x 288 px, the face 76 px across
// and turned 4 degrees. The template is the face's bounding box cut from
// the first frame, as a user cuts one. Its dots make it nearly the same
// under a quarter turn: the paper's eq. 5 hardly tells the turns (or a
// second prototype's hypotheses) apart, and a fit started at the wrong turn
// stays there with its dots just off the edges. Beside 16 more prototypes
// the cut is found when the image proposes it: the pose votes of a lattice
// covering the image (coverage_schedule.h).
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "run_length.h"
#include "scene_drawing.h"

namespace
{
const cv::Size kFrameSize(384, 288);
const cv::Point2d kFaceCentre(214.0, 118.0);
constexpr double kFaceSide = 76.0;     // px
constexpr double kFaceTurnDeg = -4.0;  // the face's turn in the frame
constexpr int kFrames = 20;
constexpr double kCornerTolerance = 3.0;  // px: every corner of the cut within it of the truth

/// Face px (the face's own frame: (0, 0) its top-left corner, kFaceSide
/// square) -> frame px.
cv::Point2d onFace(double u, double v)
{
  const double a = kFaceTurnDeg * M_PI / 180.0;
  const double x = u - 0.5 * kFaceSide, y = v - 0.5 * kFaceSide;
  return {kFaceCentre.x + std::cos(a) * x - std::sin(a) * y, kFaceCentre.y + std::sin(a) * x + std::cos(a) * y};
}

/// The background: a mid grey collage of blobs and bars drawn from a fixed
/// stream (the same in every frame), kept off the face.
cv::Mat clutteredBackground()
{
  cv::Mat frame(kFrameSize, CV_8UC1, cv::Scalar(128));
  cv::RNG rng(20261207);
  for (int k = 0; k < 40; ++k)
  {
    const cv::Point centre(rng.uniform(0, kFrameSize.width), rng.uniform(0, kFrameSize.height));
    if (std::hypot(centre.x - kFaceCentre.x, centre.y - kFaceCentre.y) < kFaceSide)
      continue;
    const cv::Scalar grey(rng.uniform(30, 230));
    if (k % 2 == 0)
      cv::ellipse(frame, centre, cv::Size(rng.uniform(6, 30), rng.uniform(6, 30)), rng.uniform(0, 180), 0, 360, grey,
                  cv::FILLED, cv::LINE_AA);
    else
      cv::line(frame, centre, centre + cv::Point(rng.uniform(-40, 40), rng.uniform(-40, 40)), grey,
               rng.uniform(2, 6), cv::LINE_AA);
  }
  return frame;
}

/// The scene: the face over the background, with its own noise per frame.
cv::Mat drawFrame(int index)
{
  cv::Mat frame = clutteredBackground();
  std::vector<cv::Point> corners;
  for (const cv::Point2d& c : {onFace(0, 0), onFace(kFaceSide, 0), onFace(kFaceSide, kFaceSide), onFace(0, kFaceSide)})
    corners.emplace_back(cvRound(c.x * 16), cvRound(c.y * 16));
  cv::fillConvexPoly(frame, corners, cv::Scalar(35), cv::LINE_AA, 4);
  // The ring: the border of a 4 x 4 grid, shifted towards the top left.
  const double spacing = 0.24 * kFaceSide;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (i == 0 || i == 3 || j == 0 || j == 3)
      {
        const cv::Point2d c = onFace(0.15 * kFaceSide + i * spacing, 0.12 * kFaceSide + j * spacing);
        cv::circle(frame, cv::Point(cvRound(c.x * 16), cvRound(c.y * 16)), cvRound(0.055 * kFaceSide * 16),
                   cv::Scalar(225), cv::FILLED, cv::LINE_AA, 4);
      }
  cv::Mat noise(frame.size(), CV_16SC1);
  cv::RNG rng(1000 + index);
  rng.fill(noise, cv::RNG::NORMAL, 0, 4);
  cv::Mat out;
  frame.convertTo(out, CV_16SC1);
  out += noise;
  out.convertTo(out, CV_8UC1);
  return out;
}

/// The face's bounding box in the frame, as a user cuts the template.
cv::Rect faceBox()
{
  std::vector<cv::Point2f> corners;
  for (const cv::Point2d& c : {onFace(0, 0), onFace(kFaceSide, 0), onFace(kFaceSide, kFaceSide), onFace(0, kFaceSide)})
    corners.emplace_back(c);
  return cv::boundingRect(corners);
}

/// What is in memory beside the cut.
enum class Company
{
  kAlone,
  kApple,
  kSixteen,  ///< the apple, the 5 drawn shapes and 10 random silhouettes
};

std::shared_ptr<const amcr::PrototypeMemory> memory(const cv::Mat& first_frame, Company company)
{
  amcr::Params p;
  auto m = std::make_shared<amcr::PrototypeMemory>();
  m->add("face", first_frame(faceBox()).clone(), p);
  if (company != Company::kAlone)
    m->add("apple", amcr_test::drawApple(true), p);
  if (company == Company::kSixteen)
  {
    for (amcr_test::ShapeId id : amcr_test::allShapes())
      m->add(amcr_test::shapeName(id), amcr_test::drawPrototype(id), p);
    for (std::uint64_t k = 1; k <= 10; ++k)
      m->add("silhouette-" + std::to_string(k), amcr_test::drawRandomSilhouette(k), p);
  }
  return m;
}

/// The first frame at which "face" is reported with every corner of the cut
/// within kCornerTolerance of where it lies in the frame (the defaults, with
/// the image's candidates); -1 if never.
int firstRightReport(const std::vector<cv::Mat>& frames, const std::shared_ptr<const amcr::PrototypeMemory>& m,
                     std::uint64_t seed)
{
  amcr::Params p;
  p.seed = seed;
  amcr::Recognizer recognizer(p, m);
  const cv::Rect box = faceBox();
  const cv::Point2d cut_corners[4] = {{0, 0}, {box.width - 1.0, 0}, {box.width - 1.0, box.height - 1.0},
                                      {0, box.height - 1.0}};
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    for (const amcr::RecognizedObject& o : recognizer.step(frames[k]).objects)
    {
      if (o.label != "face")
        continue;
      double worst = 0.0;
      for (const cv::Point2d& c : cut_corners)
      {
        const cv::Point2d truth = c + cv::Point2d(box.x, box.y);  // the cut is the frame's own pixels
        worst = std::max(worst, cv::norm(amcr::applyAffine(o.prototype_to_image, c) - truth));
      }
      if (worst <= kCornerTolerance)
        return static_cast<int>(k);
    }
  }
  return -1;
}

class DottedFace : public ::testing::TestWithParam<Company>
{
protected:
  static void SetUpTestSuite()
  {
    frames_ = std::make_unique<std::vector<cv::Mat>>();
    for (int k = 0; k < kFrames; ++k)
      frames_->push_back(drawFrame(k));
  }
  static void TearDownTestSuite() { frames_.reset(); }
  static std::unique_ptr<std::vector<cv::Mat>> frames_;
};
std::unique_ptr<std::vector<cv::Mat>> DottedFace::frames_;

TEST_P(DottedFace, FoundByEverySeed)
{
  const Company company = GetParam();
  const auto m = memory(frames_->front(), company);
  ASSERT_TRUE((*m)[0].isTemplate());
  const char* const beside[] = {", alone", ", with the apple", ", with 16 others"};
  for (const int seed : amcr_test::firstOf(std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}, 3))
  {
    const int first =
        firstRightReport(*frames_, m, static_cast<std::uint64_t>(seed));
    std::cout << "[ face     ] seed " << seed << beside[static_cast<int>(company)]
              << ": first report at the right place at frame " << first << "\n";
    EXPECT_GE(first, 0) << "seed " << seed << beside[static_cast<int>(company)]
                        << ": the face is never reported at its place in " << kFrames << " frames";
  }
}

std::string companyName(const ::testing::TestParamInfo<Company>& info)
{
  switch (info.param)
  {
    case Company::kAlone:
      return "Alone";
    case Company::kApple:
      return "WithApple";
    case Company::kSixteen:
      break;
  }
  return "WithSixteen";
}

INSTANTIATE_TEST_SUITE_P(AloneAndWithOthers, DottedFace,
                         ::testing::Values(Company::kAlone, Company::kApple, Company::kSixteen), companyName);
}  // namespace
