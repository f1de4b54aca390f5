// Bad input gets a clear error, never a crash: the
// prototype directory, input images of every type, V-particle displacements,
// and recovery after an error.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "scene_drawing.h"
#include "warning_lines.h"

namespace
{
using amcr_test::ShapeId;

using Warnings = amcr_test::WarningLines;

void writeGarbage(const std::string& path)
{
  std::ofstream out(path, std::ios::binary);
  const unsigned char bytes[] = {0x00, 0x13, 0x37, 0xde, 0xad, 0xbe, 0xef, 0x42, 0x89, 0x50, 0x4e, 0x47, 0xff, 0x01};
  for (int k = 0; k < 40; ++k)
    out.write(reinterpret_cast<const char*>(bytes), sizeof(bytes));
}

void writeImage(const std::string& path, const cv::Mat& image) { ASSERT_TRUE(cv::imwrite(path, image)) << path; }

amcr::Params smallParams()
{
  amcr::Params p;
  p.num_v_particles = 10;
  p.m_particles_per_prototype = 10;
  p.seed = 3;
  return p;
}

// ---------------------------------------------------------------------------
// The prototype directory

TEST(LoadDirectory, MissingDirectoryIsAMemoryError)
{
  amcr_test::TempDir dir;
  EXPECT_THROW(amcr::PrototypeMemory::loadDirectory(dir.file("no_such_directory"), amcr::Params()), amcr::MemoryError);
  // A file is not a directory.
  writeImage(dir.file("arrow.png"), amcr_test::drawPrototype(ShapeId::kArrow));
  EXPECT_THROW(amcr::PrototypeMemory::loadDirectory(dir.file("arrow.png"), amcr::Params()), amcr::MemoryError);
}

TEST(LoadDirectory, EmptyDirectoryIsAMemoryError)
{
  amcr_test::TempDir dir;
  EXPECT_THROW(amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params()), amcr::MemoryError);
}

TEST(LoadDirectory, UnreadableFileIsSkippedWithAWarningNamingIt)
{
  amcr_test::TempDir dir;
  writeGarbage(dir.file("x.png"));
  writeImage(dir.file("arrow.png"), amcr_test::drawPrototype(ShapeId::kArrow));
  Warnings warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params(), warnings.sink());
  ASSERT_EQ(memory.size(), 1u);
  EXPECT_EQ(memory[0].label(), "arrow");
  EXPECT_EQ(memory.find("arrow"), 0);
  EXPECT_EQ(memory.find("x"), -1);
  EXPECT_TRUE(warnings.mention("x.png")) << "warnings:" << warnings.all();
  EXPECT_FALSE(warnings.mention("arrow.png")) << "the good file was warned about:" << warnings.all();
}

TEST(LoadDirectory, ImageWithoutEdgesIsSkippedWithAWarningNamingIt)
{
  amcr_test::TempDir dir;
  writeImage(dir.file("flat.png"), cv::Mat(120, 160, CV_8UC1, cv::Scalar(128)));
  writeImage(dir.file("star.png"), amcr_test::drawPrototype(ShapeId::kStar, false));  // black on white
  writeImage(dir.file("crescent.png"), amcr_test::drawPrototype(ShapeId::kCrescent));
  Warnings warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params(), warnings.sink());
  ASSERT_EQ(memory.size(), 2u);
  // Sorted by file name; label = file name without extension.
  EXPECT_EQ(memory[0].label(), "crescent");
  EXPECT_EQ(memory[1].label(), "star");
  EXPECT_TRUE(warnings.mention("flat.png")) << "warnings:" << warnings.all();
  EXPECT_EQ(warnings.lines.size(), 1u) << "warnings:" << warnings.all();
}

TEST(LoadDirectory, OnlyBadFilesIsAMemoryError)
{
  amcr_test::TempDir dir;
  writeGarbage(dir.file("x.png"));
  writeImage(dir.file("flat.png"), cv::Mat(50, 50, CV_8UC1, cv::Scalar(0)));
  std::ofstream(dir.file("notes.txt")) << "not an image\n";
  Warnings warnings;
  EXPECT_THROW(amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params(), warnings.sink()), amcr::MemoryError);
  EXPECT_TRUE(warnings.mention("x.png")) << "warnings:" << warnings.all();
  EXPECT_TRUE(warnings.mention("flat.png")) << "warnings:" << warnings.all();
}

TEST(LoadDirectory, WithoutASinkBadFilesAreStillSkipped)
{
  amcr_test::TempDir dir;
  writeGarbage(dir.file("x.png"));
  writeImage(dir.file("ell.png"), amcr_test::drawPrototype(ShapeId::kEll));
  EXPECT_EQ(amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params()).size(), 1u);
}

TEST(PrototypeMemoryAdd, DuplicateLabelOrNoShapeIsAMemoryError)
{
  amcr::PrototypeMemory memory;
  memory.add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), amcr::Params());
  EXPECT_THROW(memory.add("arrow", amcr_test::drawPrototype(ShapeId::kStar), amcr::Params()), amcr::MemoryError);
  EXPECT_THROW(memory.add("flat", cv::Mat(64, 64, CV_8UC1, cv::Scalar(200)), amcr::Params()), amcr::MemoryError);
  EXPECT_THROW(memory.add("empty", cv::Mat(), amcr::Params()), amcr::MemoryError);
  EXPECT_EQ(memory.size(), 1u);
  EXPECT_GT(memory.tableBytes(), 0u);
}

// ---------------------------------------------------------------------------
// The recognizer

class RecognizerInput : public ::testing::Test
{
protected:
  // One memory and one frame for the whole suite (the memory is immutable).
  static void SetUpTestSuite()
  {
    auto memory = std::make_shared<amcr::PrototypeMemory>();
    memory->add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), smallParams());
    memory->add("star", amcr_test::drawPrototype(ShapeId::kStar), smallParams());
    memory_ = memory;
    amcr_test::Scene scene;
    scene.objects.push_back({ShapeId::kArrow,
                             amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240}, 0.3, 0.9, 0.9, 0.1)});
    scene.clutter.seed = 5;
    frame_ = amcr_test::renderSequence(scene, 1)[0];
  }
  static void TearDownTestSuite()
  {
    memory_.reset();
    frame_.release();
  }

  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
  static cv::Mat frame_;  // CV_8UC1, 640x480
};
std::shared_ptr<const amcr::PrototypeMemory> RecognizerInput::memory_;
cv::Mat RecognizerInput::frame_;

TEST_F(RecognizerInput, EmptyImageIsAnInputError)
{
  amcr::Recognizer recognizer(smallParams(), memory_);
  EXPECT_THROW(recognizer.step(cv::Mat()), amcr::InputError);
}

TEST_F(RecognizerInput, SixteenBitBgrBgraAndFloatImagesAreConverted)
{
  cv::Mat u16, bgr, bgra, f32, f32_255;
  frame_.convertTo(u16, CV_16UC1, 257.0);
  cv::cvtColor(frame_, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(frame_, bgra, cv::COLOR_GRAY2BGRA);
  frame_.convertTo(f32, CV_32FC1, 1.0 / 255.0);  // in [0, 1]
  for (const cv::Mat& image : {frame_, u16, bgr, bgra, f32})
  {
    amcr::Recognizer recognizer(smallParams(), memory_);
    amcr::RecognitionResult result;
    ASSERT_NO_THROW(result = recognizer.step(image)) << cv::typeToString(image.type());
    EXPECT_EQ(result.iteration, 1) << cv::typeToString(image.type());
    EXPECT_EQ(recognizer.vParticles().size(), 10u) << cv::typeToString(image.type());
  }
  // Converted, not merely accepted: the 16-bit and BGRA versions of a frame
  // drive the filter exactly like the 8-bit grey frame (same seed).
  amcr::Recognizer grey(smallParams(), memory_), wide(smallParams(), memory_), colour(smallParams(), memory_);
  grey.step(frame_);
  wide.step(u16);
  colour.step(bgra);
  ASSERT_EQ(grey.vParticles().size(), wide.vParticles().size());
  for (std::size_t i = 0; i < grey.vParticles().size(); ++i)
  {
    EXPECT_EQ(grey.vParticles()[i].x, wide.vParticles()[i].x) << "16-bit, V-particle " << i;
    EXPECT_EQ(grey.vParticles()[i].x, colour.vParticles()[i].x) << "BGRA, V-particle " << i;
  }
}

TEST_F(RecognizerInput, UnsupportedTypesAreRefusedNamingTheType)
{
  struct Case
  {
    int type;
    std::string name_part;
  };
  for (const Case& c : {Case{CV_64FC2, "64F"}, Case{CV_8SC1, "8S"}})
  {
    amcr::Recognizer recognizer(smallParams(), memory_);
    const cv::Mat image(480, 640, c.type, cv::Scalar::all(0));
    try
    {
      recognizer.step(image);
      ADD_FAILURE() << cv::typeToString(c.type) << " accepted";
    }
    catch (const amcr::InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(c.name_part), std::string::npos)
          << "the message does not name " << cv::typeToString(c.type) << ": " << e.what();
    }
  }
}

TEST_F(RecognizerInput, WrongDisplacementCountIsAnInputError)
{
  amcr::Recognizer recognizer(smallParams(), memory_);
  recognizer.step(frame_);
  ASSERT_EQ(recognizer.vParticles().size(), 10u);
  EXPECT_THROW(recognizer.moveVParticles(std::vector<cv::Point2f>(9)), amcr::InputError);
  EXPECT_THROW(recognizer.moveVParticles(std::vector<cv::Point2f>(11)), amcr::InputError);
  EXPECT_THROW(recognizer.moveVParticles({}), amcr::InputError);
  std::vector<cv::Point2f> nan_flow(10, cv::Point2f(1.f, 1.f));
  nan_flow[4].x = std::nanf("");
  EXPECT_THROW(recognizer.moveVParticles(nan_flow), amcr::InputError);
}

// The right count moves each V-particle by its displacement and leaves the
// M-particles (its correspondence) where they are.
TEST_F(RecognizerInput, DisplacementMovesOnlyTheVParticles)
{
  amcr::Recognizer recognizer(smallParams(), memory_);
  recognizer.step(frame_);
  const std::vector<amcr::VParticle> v0 = recognizer.vParticles();
  const std::vector<float> mx0 = recognizer.mParticles().x, my0 = recognizer.mParticles().y;
  std::vector<cv::Point2f> flow;
  for (std::size_t i = 0; i < v0.size(); ++i)
    flow.emplace_back(1.5f - 0.5f * i, 2.f);
  recognizer.moveVParticles(flow);
  for (std::size_t i = 0; i < v0.size(); ++i)
  {
    if (v0[i].x < 10 || v0[i].y < 10 || v0[i].x > 629 || v0[i].y > 469)
      continue;  // near the border the move may be clamped
    EXPECT_FLOAT_EQ(recognizer.vParticles()[i].x, v0[i].x + flow[i].x) << "V-particle " << i;
    EXPECT_FLOAT_EQ(recognizer.vParticles()[i].y, v0[i].y + flow[i].y) << "V-particle " << i;
  }
  EXPECT_EQ(recognizer.mParticles().x, mx0);
  EXPECT_EQ(recognizer.mParticles().y, my0);
  EXPECT_NO_THROW(recognizer.step(frame_));
}

TEST_F(RecognizerInput, EmptyMemoryIsAMemoryError)
{
  EXPECT_THROW(amcr::Recognizer(smallParams(), std::make_shared<amcr::PrototypeMemory>()), amcr::MemoryError);
  EXPECT_THROW(amcr::Recognizer(smallParams(), nullptr), amcr::MemoryError);
  amcr::Recognizer recognizer(smallParams(), memory_);
  EXPECT_THROW(recognizer.setMemory(std::make_shared<amcr::PrototypeMemory>()), amcr::MemoryError);
  EXPECT_NO_THROW(recognizer.step(frame_)) << "a refused memory must leave the old one in place";
}

TEST_F(RecognizerInput, InvalidParametersAreAParameterError)
{
  amcr::Params p = smallParams();
  p.p_outlier = 1.5;
  EXPECT_THROW(amcr::Recognizer(p, memory_), amcr::ParameterError);
}

// A refused image changes nothing: the next good step carries on as if the
// bad one had never come.
TEST_F(RecognizerInput, WorksAfterAnError)
{
  amcr::Recognizer recognizer(smallParams(), memory_), reference(smallParams(), memory_);
  ASSERT_NO_THROW(recognizer.step(frame_));
  reference.step(frame_);
  const std::vector<amcr::VParticle> v_before = recognizer.vParticles();

  EXPECT_THROW(recognizer.step(cv::Mat()), amcr::InputError);
  EXPECT_THROW(recognizer.step(cv::Mat(480, 640, CV_64FC2, cv::Scalar::all(0))), amcr::InputError);
  EXPECT_THROW(recognizer.moveVParticles(std::vector<cv::Point2f>(3)), amcr::InputError);
  ASSERT_EQ(recognizer.vParticles().size(), v_before.size());
  for (std::size_t i = 0; i < v_before.size(); ++i)
    EXPECT_EQ(std::memcmp(&recognizer.vParticles()[i], &v_before[i], sizeof(amcr::VParticle)), 0)
        << "V-particle " << i << " changed by a refused input";

  amcr::RecognitionResult result;
  ASSERT_NO_THROW(result = recognizer.step(frame_));
  EXPECT_EQ(result.iteration, 2);
  EXPECT_EQ(recognizer.iteration(), 2);
  reference.step(frame_);
  ASSERT_EQ(recognizer.mParticles().x, reference.mParticles().x) << "the refused inputs changed the filter";
  EXPECT_EQ(recognizer.mParticles().theta, reference.mParticles().theta);
}

// A new image size re-seeds the V-particles inside the new image.
TEST_F(RecognizerInput, ImageSizeChangeReseeds)
{
  amcr::Recognizer recognizer(smallParams(), memory_);
  recognizer.step(frame_);
  cv::Mat small;
  cv::resize(frame_, small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
  ASSERT_NO_THROW(recognizer.step(small));
  ASSERT_EQ(recognizer.vParticles().size(), 10u);
  for (const amcr::VParticle& v : recognizer.vParticles())
  {
    EXPECT_TRUE(v.x >= 0.f && v.x <= 319.f && v.y >= 0.f && v.y <= 239.f) << "(" << v.x << ", " << v.y << ")";
  }
  // A tiny image is no crash either: processed, or refused with an InputError.
  for (int side : {1, 2, 3})
  {
    try
    {
      recognizer.step(cv::Mat(side, side, CV_8UC1, cv::Scalar(100)));
    }
    catch (const amcr::InputError&)
    {
    }
  }
  EXPECT_NO_THROW(recognizer.step(frame_));
}
}  // namespace

namespace
{
// An entry whose type cannot be read (a symbolic link loop) is one more unusable file, not the end of the load.
TEST(LoadDirectory, SymlinkLoopIsSkippedWithAWarningNamingIt)
{
  amcr_test::TempDir dir;
  writeImage(dir.file("arrow.png"), amcr_test::drawPrototype(ShapeId::kArrow));
  std::filesystem::create_symlink(dir.file("loop_b.png"), dir.file("loop_a.png"));
  std::filesystem::create_symlink(dir.file("loop_a.png"), dir.file("loop_b.png"));
  std::filesystem::create_symlink(dir.file("missing.png"), dir.file("dangling.png"));
  Warnings warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir.path(), amcr::Params(), warnings.sink());
  ASSERT_EQ(memory.size(), 1u);
  EXPECT_EQ(memory[0].label(), "arrow");
  EXPECT_TRUE(warnings.mention("loop_a.png")) << "warnings:" << warnings.all();
  EXPECT_TRUE(warnings.mention("loop_b.png")) << "warnings:" << warnings.all();
  EXPECT_TRUE(warnings.mention("dangling.png")) << "warnings:" << warnings.all();
  // A loop as the directory itself is a MemoryError that says why.
  std::filesystem::create_symlink(dir.file("self"), dir.file("self"));
  try
  {
    amcr::PrototypeMemory::loadDirectory(dir.file("self"), amcr::Params());
    ADD_FAILURE() << "no MemoryError";
  }
  catch (const amcr::MemoryError& e)
  {
    EXPECT_NE(std::string(e.what()).find("symbolic links"), std::string::npos) << e.what();
  }
}
}  // namespace
