// Resource bounds, so that a parameter file or an input cannot exhaust the
// memory before anything is checked: M-particles, input pixels and table
// memory are checked up front against the constants of resource_bounds.h,
// with an error that gives the figure and the bound; the documented use
// stays inside. Parameters that make each other meaningless are refused.
#include <fstream>
#include <functional>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/memory/table_stride_choice.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

/// The message of the `Exception` that `action` throws ("" when none).
template <class Exception>
std::string errorOf(const std::function<void()>& action)
{
  try
  {
    action();
  }
  catch (const Exception& e)
  {
    return e.what();
  }
  return "";
}

std::shared_ptr<const amcr::PrototypeMemory> memoryOf(int count, int prototype_size = 32)
{
  const ShapeId shapes[] = {ShapeId::kArrow, ShapeId::kStar, ShapeId::kCrescent, ShapeId::kEll};
  amcr::Params params;
  params.prototype_size = prototype_size;
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  for (int i = 0; i < count; ++i)
    memory->add("shape" + std::to_string(i), amcr_test::drawPrototype(shapes[i % 4]), params);
  return memory;
}

TEST(ResourceBounds, TheDocumentedUseIsInside)
{
  EXPECT_LE(60LL * 60 * 70, amcr::kMaxMParticles / 10);  // defaults, the 70-prototype benchmark
  EXPECT_LE(60LL * 60 * 1000, amcr::kMaxMParticles);
  EXPECT_LE(1280LL * 720, amcr::kMaxImagePixels / 10);
  EXPECT_LE(1000 * amcr::maxTableBytesPerPrototype(128), amcr::kMaxTableBytes / 2);
}

TEST(ResourceBounds, CampaignCountsAreRefusedAtConstructionWithTheFigureAndTheBound)
{
  amcr::Params params;
  params.num_v_particles = 5000;
  params.m_particles_per_prototype = 5000;
  const std::string error =
      errorOf<amcr::ParameterError>([&] { amcr::Recognizer recognizer(params, memoryOf(3)); });
  EXPECT_NE(error.find("25000000"), std::string::npos) << error;  // 5000 x 5000, even before the prototypes
  EXPECT_NE(error.find("8000000"), std::string::npos) << error;
}

TEST(ResourceBounds, PrototypesMultiplyTheParticles)
{
  amcr::Params params;
  params.num_v_particles = 2000;
  params.m_particles_per_prototype = 1500;  // 3,000,000 per prototype: valid alone
  params.m_particles_per_v = 0;             // the paper's count, which the prototypes multiply
  EXPECT_NO_THROW(params.validate());
  const std::string error =
      errorOf<amcr::ParameterError>([&] { amcr::Recognizer recognizer(params, memoryOf(3)); });
  EXPECT_NE(error.find("9000000 M-particles"), std::string::npos) << error;
  EXPECT_NE(error.find("3 prototypes"), std::string::npos) << error;
  EXPECT_NE(error.find("bound of 8000000"), std::string::npos) << error;
  // A prior that leaves one prototype active brings it within the bound.
  params.prototype_priors = {{"shape1", 0.0}, {"shape2", 0.0}};
  EXPECT_NO_THROW(amcr::Recognizer(params, memoryOf(3)));
  // A memory swap that would pass the bound is refused, and the old memory stays.
  params.prototype_priors.clear();
  amcr::Recognizer recognizer(params, memoryOf(1));
  EXPECT_THROW(recognizer.setMemory(memoryOf(3)), amcr::ParameterError);
  EXPECT_EQ(recognizer.memory().size(), 1u);
}

TEST(ResourceBounds, InputImageAboveThePixelBoundIsRefused)
{
  amcr::Params params;
  params.num_v_particles = 10;
  params.m_particles_per_prototype = 10;
  amcr::Recognizer recognizer(params, memoryOf(1));
  const cv::Mat huge(4400, 8000, CV_8UC1, cv::Scalar(0));
  const std::string error = errorOf<amcr::InputError>([&] { recognizer.step(huge); });
  EXPECT_NE(error.find("8000 x 4400 = 35200000 pixels"), std::string::npos) << error;
  EXPECT_NE(error.find("33177600"), std::string::npos) << error;
  EXPECT_NO_THROW(recognizer.step(cv::Mat(720, 1280, CV_8UC1, cv::Scalar(0))));
}

TEST(ResourceBounds, TableMemoryAboveTheBoundIsRefusedBeforeBuilding)
{
  amcr_test::TempDir dir;
  amcr::Params params;
  params.prototype_size = 512;  // up to 29.5 MB of table per prototype
  params.table_stride = 1;      // given: the stride chosen by default (0) would fit them at 4
  const long files = amcr::kMaxTableBytes / amcr::maxTableBytesPerPrototype(512) + 1;
  for (long i = 0; i < files; ++i)
    std::ofstream(dir.file("p" + std::to_string(i) + ".png")) << "x";
  const std::string error =
      errorOf<amcr::MemoryError>([&] { amcr::PrototypeMemory::loadDirectory(dir.path(), params); });
  EXPECT_NE(error.find(std::to_string(files) + " x "), std::string::npos) << error;
  EXPECT_NE(error.find("bound of 4.29 GB"), std::string::npos) << error;
}

TEST(ParamsConsistency, MinSupportAboveTheVParticlesIsRefusedNamingBoth)
{
  amcr::Params params;
  params.num_v_particles = 10;
  params.min_support = 11;
  const std::string error = errorOf<amcr::ParameterError>([&] { params.validate(); });
  EXPECT_NE(error.find("min_support"), std::string::npos) << error;
  EXPECT_NE(error.find("num_v_particles"), std::string::npos) << error;
  params.min_support = 10;
  EXPECT_NO_THROW(params.validate());
}

TEST(ParamsConsistency, InjectionAndReseedingTakingEveryMParticleAreRefused)
{
  amcr::Params params;
  params.injection_fraction = 0.6;
  params.m_reseed_fraction = 0.4;
  const std::string error = errorOf<amcr::ParameterError>([&] { params.validate(); });
  EXPECT_NE(error.find("injection_fraction"), std::string::npos) << error;
  EXPECT_NE(error.find("m_reseed_fraction"), std::string::npos) << error;
  params.m_reseed_fraction = 0.3;
  EXPECT_NO_THROW(params.validate());
}
}  // namespace
