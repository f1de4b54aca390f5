// The edits of a running memory without ROS (amcr/memory/memory_edits.h): a
// rebuild loads the directory again and keeps what was taught and removed, a
// load forgets it, and a teach or a removal that must be refused says why.
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "amcr/base/errors.h"
#include "amcr/memory/memory_edits.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

/// A directory holding arrow.png and star.png.
class MemoryEditsTest : public testing::Test
{
protected:
  void SetUp() override
  {
    for (const ShapeId id : {ShapeId::kArrow, ShapeId::kStar})
      ASSERT_TRUE(cv::imwrite(dir_.file(amcr_test::shapeName(id) + ".png"), amcr_test::drawPrototype(id)));
  }

  /// Reads the directory as the nodelet does, counting the reads.
  amcr::MemoryEdits::DirectoryReader reader()
  {
    return [this](const std::string& directory, const amcr::MemoryParams& params) {
      ++reads_;
      return amcr::PrototypeMemory::loadDirectory(directory, params);
    };
  }

  amcr_test::TempDir dir_;
  int reads_ = 0;
};

std::vector<std::string> labels(const amcr::PrototypeMemory& memory)
{
  std::vector<std::string> out;
  for (std::size_t i = 0; i < memory.size(); ++i)
    out.push_back(memory[i].label());
  return out;
}

TEST_F(MemoryEditsTest, ARebuildKeepsWhatWasTaughtAndRemovedALoadForgetsIt)
{
  amcr::MemoryEdits edits;
  edits.loaded(dir_.path());
  edits.addTaught("crescent", amcr_test::drawPrototype(ShapeId::kCrescent));
  edits.addRemoval("star");
  const auto rebuilt = edits.rebuild(amcr::Params(), reader());
  EXPECT_EQ(reads_, 1);
  EXPECT_EQ(labels(*rebuilt), (std::vector<std::string>{"arrow", "crescent"}));

  // Removing a label taught in this session forgets the shape: a later rebuild does not bring it back.
  edits.addRemoval("crescent");
  EXPECT_EQ(labels(*edits.rebuild(amcr::Params(), reader())), (std::vector<std::string>{"arrow"}));

  edits.loaded(dir_.path());
  EXPECT_TRUE(edits.taught().empty());
  EXPECT_TRUE(edits.removedLabels().empty());
  EXPECT_EQ(labels(*edits.rebuild(amcr::Params(), reader())), (std::vector<std::string>{"arrow", "star"}));
}

TEST_F(MemoryEditsTest, WithoutADirectoryOnlyTheTaughtShapesAndNothingLeftIsAnError)
{
  amcr::MemoryEdits edits;
  edits.addTaught("flag", amcr_test::drawPrototype(ShapeId::kFlag));
  EXPECT_EQ(labels(*edits.rebuild(amcr::Params(), reader())), (std::vector<std::string>{"flag"}));
  EXPECT_EQ(reads_, 0) << "no directory to read";

  edits.loaded(dir_.path());
  edits.addRemoval("arrow");
  edits.addRemoval("star");
  EXPECT_THROW(edits.rebuild(amcr::Params(), reader()), amcr::MemoryError);
}

TEST_F(MemoryEditsTest, ARebuildTakesTheNewTableParameters)
{
  amcr::MemoryEdits edits;
  edits.loaded(dir_.path());
  edits.addTaught("crescent", amcr_test::drawPrototype(ShapeId::kCrescent));
  const auto before = edits.rebuild(amcr::Params(), reader());
  amcr::Params params;
  params.prototype_size = 64;  // half the default
  const auto rebuilt = edits.rebuild(params, reader());
  ASSERT_EQ(rebuilt->size(), before->size());
  for (std::size_t i = 0; i < rebuilt->size(); ++i)  // the taught one too
    EXPECT_LT((*rebuilt)[i].mask().cols, (*before)[i].mask().cols) << (*rebuilt)[i].label();
}

TEST_F(MemoryEditsTest, ATeachThatMustBeRefusedSaysWhy)
{
  amcr::MemoryEdits edits;
  edits.loaded(dir_.path());
  const auto memory = edits.rebuild(amcr::Params(), reader());
  std::string path = "(unchanged)";
  const auto refusal = [&](const std::string& label, bool save) {
    return edits.teachRefusal(memory.get(), label, save, path);
  };
  EXPECT_NE(refusal("", false).find("empty"), std::string::npos);
  EXPECT_NE(refusal(std::string(65, 'a'), false).find("longer than 64"), std::string::npos);
  EXPECT_NE(refusal(".hidden", false).find("starts with '.'"), std::string::npos);
  EXPECT_NE(refusal("bad/label", false).find("character"), std::string::npos);
  EXPECT_NE(refusal("arrow", false).find("taken (1 prototypes)"), std::string::npos);
  EXPECT_EQ(refusal("mug_2.v1", false), "");
  EXPECT_EQ(path, "") << "nothing to save";

  EXPECT_EQ(refusal("mug", true), "");
  EXPECT_EQ(path, dir_.file("mug.png"));
  std::ofstream(dir_.file("mug.png")) << "x";
  EXPECT_NE(refusal("mug", true).find("exists already"), std::string::npos);
  EXPECT_EQ(path, "");

  amcr::MemoryEdits no_directory;
  EXPECT_NE(no_directory.teachRefusal(nullptr, "mug", true, path).find("nowhere to save"), std::string::npos);
  EXPECT_EQ(no_directory.teachRefusal(nullptr, "mug", false, path), "") << "the first prototype of a memory";
}

TEST_F(MemoryEditsTest, ARemovalThatMustBeRefusedSaysWhy)
{
  amcr::MemoryEdits edits;
  edits.loaded(dir_.path());
  const auto memory = edits.rebuild(amcr::Params(), reader());
  EXPECT_NE(amcr::MemoryEdits::removalRefusal(memory.get(), "mug").find("no label 'mug'"), std::string::npos);
  EXPECT_NE(amcr::MemoryEdits::removalRefusal(nullptr, "arrow").find("no label"), std::string::npos);
  EXPECT_EQ(amcr::MemoryEdits::removalRefusal(memory.get(), "arrow"), "");

  edits.addRemoval("star");
  const auto one_left = edits.rebuild(amcr::Params(), reader());
  EXPECT_NE(amcr::MemoryEdits::removalRefusal(one_left.get(), "arrow").find("only label"), std::string::npos);
}
}  // namespace
