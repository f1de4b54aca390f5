// Class labels (a label may have several instances): a prototype directory of label directories and
// loose files, what each bad entry gets, priors over labels, and tracks that
// keep their id when another instance of the same label matches.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "amcr/base/errors.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/prototype_prior.h"
#include "amcr/extraction/track_registry.h"
#include "scene_drawing.h"
#include "warning_lines.h"

namespace
{
using amcr_test::ShapeId;
namespace fs = std::filesystem;

amcr::Params smallTables()
{
  amcr::Params p;
  p.prototype_size = 48;
  p.table_cache_dir = "none";
  return p;
}

void writeImage(const std::string& path, const cv::Mat& image)
{
  fs::create_directories(fs::path(path).parent_path());
  ASSERT_TRUE(cv::imwrite(path, image)) << path;
}

void writeText(const std::string& path, const std::string& text)
{
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

std::vector<std::string> labelsOf(const amcr::PrototypeMemory& memory)
{
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < memory.size(); ++i)
    labels.push_back(memory[i].label());
  return labels;
}

std::vector<std::string> instancesOf(const amcr::PrototypeMemory& memory)
{
  std::vector<std::string> instances;
  for (std::size_t i = 0; i < memory.size(); ++i)
    instances.push_back(memory[i].instance());
  return instances;
}

TEST(PrototypeLabels, LabelDirectoriesAndLooseFilesGiveTheirLabels)
{
  amcr_test::TempDir dir;
  writeImage(dir.file("star/star-b.png"), amcr_test::drawPrototype(ShapeId::kStar));
  writeImage(dir.file("star/star-a.png"), amcr_test::drawPrototype(ShapeId::kStar, false));
  writeImage(dir.file("flag/one.png"), amcr_test::drawPrototype(ShapeId::kFlag));
  writeImage(dir.file("arrow.png"), amcr_test::drawPrototype(ShapeId::kArrow));
  writeImage(dir.file("ell.png"), amcr_test::drawPrototype(ShapeId::kEll));
  amcr_test::WarningLines warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir.path(), smallTables(), warnings.sink());

  // Sorted by label, then instance.
  EXPECT_EQ(labelsOf(memory), (std::vector<std::string>{"arrow", "ell", "flag", "star", "star"}));
  EXPECT_EQ(instancesOf(memory),
            (std::vector<std::string>{"arrow.png", "ell.png", "flag/one.png", "star/star-a.png", "star/star-b.png"}));
  EXPECT_EQ(memory.labels(), (std::vector<std::string>{"arrow", "ell", "flag", "star"}));
  EXPECT_EQ(memory.instancesOf("star"), (std::vector<int>{3, 4}));
  EXPECT_EQ(memory.find("star"), 3);
  EXPECT_EQ(memory.findInstance("star/star-b.png"), 4);
  EXPECT_EQ(memory.findInstance("star"), -1);
  EXPECT_TRUE(warnings.lines.empty()) << warnings.all();
}

TEST(PrototypeLabels, EachBadEntryIsReportedByNameAndTheRestLoads)
{
  amcr_test::TempDir dir;
  writeImage(dir.file("star/good.png"), amcr_test::drawPrototype(ShapeId::kStar));
  writeText(dir.file("star/broken.png"), "not a png at all");           // unreadable file
  writeImage(dir.file("star/deeper/lost.png"), amcr_test::drawPrototype(ShapeId::kEll));  // one level only
  fs::create_directories(dir.file("empty"));                              // empty label directory
  writeImage(dir.file("flag/flag-1.png"), amcr_test::drawPrototype(ShapeId::kFlag));
  writeImage(dir.file("flag.png"), amcr_test::drawPrototype(ShapeId::kCrescent));  // label taken by flag/
  writeImage(dir.file("arrow.png"), amcr_test::drawPrototype(ShapeId::kArrow));
  writeImage(dir.file("arrow.tif"), amcr_test::drawPrototype(ShapeId::kEll));      // label taken by arrow.png
  writeText(dir.file("notes.txt"), "a file that is no image\n");         // non-image file
  amcr_test::WarningLines warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir.path(), smallTables(), warnings.sink());

  EXPECT_EQ(instancesOf(memory), (std::vector<std::string>{"arrow.png", "flag/flag-1.png", "star/good.png"}));
  EXPECT_TRUE(warnings.mention("broken.png")) << warnings.all();
  EXPECT_TRUE(warnings.mention("deeper", "one level")) << warnings.all();
  EXPECT_TRUE(warnings.mention("empty", "holds no files")) << warnings.all();
  EXPECT_TRUE(warnings.mention("flag.png", "label directory 'flag'")) << warnings.all();
  EXPECT_TRUE(warnings.mention("arrow.tif", "taken")) << warnings.all();
  EXPECT_TRUE(warnings.mention("notes.txt")) << warnings.all();
  EXPECT_EQ(warnings.lines.size(), 6u) << warnings.all();
}

TEST(PrototypeLabels, OnlyEmptyLabelDirectoriesIsAMemoryError)
{
  amcr_test::TempDir dir;
  fs::create_directories(dir.file("a"));
  fs::create_directories(dir.file("b"));
  amcr_test::WarningLines warnings;
  EXPECT_THROW(amcr::PrototypeMemory::loadDirectory(dir.path(), smallTables(), warnings.sink()), amcr::MemoryError);
  EXPECT_TRUE(warnings.mention("'" + dir.file("a") + "'", "holds no files")) << warnings.all();
}

TEST(PrototypeLabels, AddTakesANewLabelOrANewInstance)
{
  amcr::PrototypeMemory memory;
  const amcr::Params params = smallTables();
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar), params);
  EXPECT_THROW(memory.add("star", amcr_test::drawPrototype(ShapeId::kEll), params), amcr::MemoryError);
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar, false), params, "star/second");
  EXPECT_THROW(memory.add("flag", amcr_test::drawPrototype(ShapeId::kFlag), params, "star/second"), amcr::MemoryError);
  EXPECT_EQ(instancesOf(memory), (std::vector<std::string>{"star", "star/second"}));
  EXPECT_EQ(memory.labels(), (std::vector<std::string>{"star"}));
}

// A label weighs the same whatever the number of its instances.
TEST(PrototypeLabels, PriorsApplyToLabels)
{
  amcr::PrototypeMemory memory;
  amcr::Params params = smallTables();
  params.m_particles_per_v = 40;
  memory.add("arrow", amcr_test::drawPrototype(ShapeId::kArrow), params);
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar), params, "star/1");
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar, false), params, "star/2");
  memory.add("star", amcr_test::drawPrototype(ShapeId::kStar, true, false), params, "star/3");
  {
    const amcr::PrototypePrior prior(memory, params);
    EXPECT_DOUBLE_EQ(prior.probability(0), 0.5);
    for (int p : {1, 2, 3})
      EXPECT_NEAR(prior.probability(p), 0.5 / 3, 1e-12) << p;
    std::vector<int> slots(4, 0);
    for (int p : prior.slots())
      ++slots[p];
    EXPECT_EQ(slots[0], 20);
    EXPECT_EQ(slots[1] + slots[2] + slots[3], 20);
  }
  params.prototype_priors = {{"star", 3.0}};
  {
    const amcr::PrototypePrior prior(memory, params);
    EXPECT_DOUBLE_EQ(prior.probability(0), 0.25);
    EXPECT_NEAR(prior.probability(1) + prior.probability(2) + prior.probability(3), 0.75, 1e-12);
  }
  params.prototype_priors = {{"star", 0.0}};
  {
    const amcr::PrototypePrior prior(memory, params);
    EXPECT_EQ(prior.activeMask(), (std::vector<bool>{true, false, false, false}));
  }
  params.prototype_priors = {{"star/1", 2.0}};  // an instance is not a label
  EXPECT_THROW(amcr::PrototypePrior(memory, params), amcr::ParameterError);
}

amcr::RecognizedObject square(const std::string& label, int prototype, double x)
{
  amcr::RecognizedObject o;
  o.label = label;
  o.instance = label + "/" + std::to_string(prototype);
  o.prototype_id = prototype;
  o.outline = {{x, 100}, {x + 80, 100}, {x + 80, 180}, {x, 180}};
  return o;
}

// The instance that matches best may change from frame to frame: the object,
// and so its track, is the label's.
TEST(PrototypeLabels, ATrackKeepsItsIdWhenAnotherInstanceMatches)
{
  amcr::TrackRegistry registry;
  std::vector<amcr::RecognizedObject> first{square("star", 3, 100), square("flag", 0, 300)};
  registry.assign(first);
  std::vector<amcr::RecognizedObject> second{square("star", 4, 104), square("arrow", 1, 302)};
  registry.assign(second);
  EXPECT_EQ(second[0].track_id, first[0].track_id);  // another star instance: the same star
  EXPECT_NE(second[1].track_id, first[1].track_id);  // another label in the flag's place: a new object
}
}  // namespace
