// The tables' stride chosen from the memory's size and table_budget_mb:
// small memories keep exact tables, a large one gets compact tables that fit,
// a given stride above the budget is used with a warning naming the budget.
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/base/resource_bounds.h"
#include "amcr/memory/table_stride_choice.h"
#include "scene_drawing.h"
#include "warning_lines.h"

namespace
{
using Warnings = amcr_test::WarningLines;

TEST(TableStrideChoice, SmallMemoriesKeepExactTablesLargeOnesFitTheBudget)
{
  const amcr::Params defaults;
  ASSERT_EQ(defaults.table_stride, 0) << "the default is the stride chosen from the memory's size";
  // At prototype_size 128 a table takes at most 160 x 160 nodes x 72 bytes = 1.84 MB at stride 1.
  for (std::size_t count : {1u, 3u, 70u, 99u, 555u})
    EXPECT_EQ(amcr::chooseTableStride(count, defaults).stride, 1) << count << " prototypes";
  const amcr::TableStrideChoice mpeg7 = amcr::chooseTableStride(1400, defaults);
  EXPECT_EQ(mpeg7.stride, 2);
  EXPECT_FALSE(mpeg7.over_budget);
  EXPECT_LE(mpeg7.table_bytes, 1024LL * 1000 * 1000);
  EXPECT_NE(mpeg7.reason.find("at table_stride 1 they would take up to 2.58 GB"), std::string::npos) << mpeg7.reason;
  EXPECT_EQ(amcr::chooseTableStride(3000, defaults).stride, 3);

  amcr::Params huge = defaults;
  huge.table_budget_mb = 16;
  const amcr::TableStrideChoice none_fits = amcr::chooseTableStride(10000, huge);
  EXPECT_EQ(none_fits.stride, 4);
  EXPECT_TRUE(none_fits.over_budget);
}

TEST(TableStrideChoice, AGivenStrideIsKeptAndOverTheBudgetSaysSo)
{
  amcr::Params given;
  given.table_stride = 1;
  const amcr::TableStrideChoice choice = amcr::chooseTableStride(1400, given);
  EXPECT_EQ(choice.stride, 1);
  EXPECT_TRUE(choice.over_budget);
  EXPECT_NE(choice.reason.find("above table_budget_mb 1024"), std::string::npos) << choice.reason;
  given.table_budget_mb = 4096;
  EXPECT_FALSE(amcr::chooseTableStride(1400, given).over_budget);
}

/// A folder of `count` drawn random silhouettes.
class DrawnMemoryTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    for (int i = 0; i < kCount; ++i)
      ASSERT_TRUE(cv::imwrite(dir_.file("shape_" + std::to_string(100 + i) + ".png"),
                              amcr_test::drawRandomSilhouette(static_cast<std::uint64_t>(i + 1))));
    // 40 tables at prototype_size 64 take at most 40 x 80 x 80 x 72 bytes =
    // 18.4 MB at stride 1 and 4.6 MB at stride 2: a budget of 16 MB stands
    // for a memory too large for exact tables.
    params_.prototype_size = 64;
    params_.table_budget_mb = 16;
    params_.table_cache_dir = "none";
  }

  static constexpr int kCount = 40;
  amcr_test::TempDir dir_;
  amcr::Params params_;
};

TEST_F(DrawnMemoryTest, TheDefaultStrideFitsTheBudgetAndSaysWhy)
{
  Warnings warnings, progress;
  const amcr::PrototypeMemory memory =
      amcr::PrototypeMemory::loadDirectory(dir_.path(), params_, warnings.sink(), progress.sink());
  ASSERT_EQ(memory.size(), static_cast<std::size_t>(kCount)) << warnings.all();
  EXPECT_EQ(memory.tableStride(), 2);
  for (std::size_t i = 0; i < memory.size(); ++i)
    EXPECT_EQ(memory[i].tableStride(), 2) << memory[i].label();
  EXPECT_LE(memory.tableBytes(), 16u * 1000 * 1000);
  EXPECT_TRUE(progress.mention("table_stride 2 (chosen", "above table_budget_mb 16")) << progress.all();
  EXPECT_FALSE(warnings.mention("table_stride")) << warnings.all();

  // A prototype taught later joins at the memory's stride.
  amcr::PrototypeMemory taught = memory;
  taught.add("taught", amcr_test::drawRandomSilhouette(99), params_);
  EXPECT_EQ(taught[taught.size() - 1].tableStride(), 2);
}

TEST_F(DrawnMemoryTest, AGivenStrideAboveTheBudgetIsUsedWithAWarning)
{
  params_.table_stride = 1;
  Warnings warnings;
  const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(dir_.path(), params_, warnings.sink());
  EXPECT_EQ(memory.tableStride(), 1);
  EXPECT_EQ(memory[0].tableStride(), 1);
  EXPECT_TRUE(warnings.mention("table_stride 1 (given)", "above table_budget_mb 16")) << warnings.all();
}

TEST_F(DrawnMemoryTest, AFewPrototypesKeepExactTables)
{
  params_.table_budget_mb = 1024;
  Warnings progress;
  const amcr::PrototypeMemory memory =
      amcr::PrototypeMemory::loadDirectory(dir_.path(), params_, amcr::PrototypeMemory::WarningSink(), progress.sink());
  EXPECT_EQ(memory.tableStride(), 1);
  EXPECT_FALSE(progress.mention("table_stride")) << "exact tables go without a word:" << progress.all();
}
}  // namespace
