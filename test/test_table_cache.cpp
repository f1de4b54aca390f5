// The table cache and the parallel table build, which spare the rebuild of
// every table at each start (the tables take most of a load): a
// second load reads the tables back byte for byte; a cache file that is
// truncated, damaged, stale (other parameters) or not a table file at all
// is detected, reported with the reason, rebuilt and replaced, never read;
// a cache that cannot be written to is a warning; the memory and the
// proposal index do not depend on the thread count.
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/table_cache.h"
#include "candidate_lists.h"
#include "scene_drawing.h"
#include "warning_lines.h"

namespace
{
namespace fs = std::filesystem;
using amcr_test::ShapeId;

using Warnings = amcr_test::WarningLines;

/// A directory of drawn prototypes and a cache directory beside it.
class TableCacheTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    images_ = root_.file("prototypes");
    cache_ = root_.file("cache");
    fs::create_directory(images_);
    for (ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
      ASSERT_TRUE(cv::imwrite(images_ + "/" + amcr_test::shapeName(id) + ".png", amcr_test::drawPrototype(id)));
    params_.prototype_size = 64;  // small tables: fast tests
    params_.table_cache_dir = cache_;
  }

  amcr::PrototypeMemory load(Warnings* warnings = nullptr) const
  {
    return amcr::PrototypeMemory::loadDirectory(images_, params_,
                                                warnings ? warnings->sink() : amcr::PrototypeMemory::WarningSink());
  }

  /// The cache file of one image (there is one per image).
  std::string cacheFile(const std::string& label) const
  {
    for (const auto& entry : fs::directory_iterator(cache_))
      if (entry.path().filename().string().rfind(label + "-", 0) == 0)
        return entry.path().string();
    return "";
  }

  std::vector<char> readAll(const std::string& path) const
  {
    std::ifstream in(path, std::ios::binary);
    return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }

  void writeAll(const std::string& path, const std::vector<char>& bytes) const
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }

  /// Loads once to fill the cache, spoils the arrow's file with `spoil`,
  /// and checks the next load refuses it with `reason`, builds the table
  /// (equal to a fresh build) and replaces the file with a sound one.
  template <typename Spoil>
  void expectRefusedAndRebuilt(Spoil spoil, const std::string& reason)
  {
    load();
    const std::string file = cacheFile("arrow");
    ASSERT_FALSE(file.empty());
    std::vector<char> bytes = readAll(file);
    spoil(bytes);
    writeAll(file, bytes);

    Warnings warnings;
    const amcr::PrototypeMemory memory = load(&warnings);
    EXPECT_EQ(memory.cacheCounts().refused, 1u);
    EXPECT_EQ(memory.cacheCounts().built, 1u);
    EXPECT_EQ(memory.cacheCounts().read, 2u);
    EXPECT_EQ(memory.cacheCounts().written, 1u);
    EXPECT_TRUE(warnings.mention(file, reason)) << "expected a line naming " << file << " and '" << reason
                                                << "'; warnings:" << warnings.all();
    EXPECT_EQ(warnings.lines.size(), 1u) << warnings.all();
    expectSameTables(memory, freshBuild());

    const amcr::PrototypeMemory again = load();
    EXPECT_EQ(again.cacheCounts().read, 3u) << "the file was not replaced by a sound one";
    EXPECT_EQ(again.cacheCounts().refused, 0u);
  }

  amcr::PrototypeMemory freshBuild() const
  {
    amcr::Params no_cache = params_;
    no_cache.table_cache_dir = "none";
    return amcr::PrototypeMemory::loadDirectory(images_, no_cache);
  }

  static void expectSameTables(const amcr::PrototypeMemory& a, const amcr::PrototypeMemory& b)
  {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      EXPECT_EQ(a[i].label(), b[i].label());
      EXPECT_TRUE(a[i].toBytes() == b[i].toBytes()) << a[i].label() << " differs";
    }
  }

  amcr_test::TempDir root_;
  std::string images_, cache_;
  amcr::Params params_;
};

TEST_F(TableCacheTest, SecondLoadReadsTheTablesBackByteForByte)
{
  Warnings warnings;
  const amcr::PrototypeMemory first = load(&warnings);
  EXPECT_EQ(first.cacheCounts().built, 3u);
  EXPECT_EQ(first.cacheCounts().written, 3u);
  EXPECT_EQ(first.cacheCounts().read, 0u);
  EXPECT_TRUE(warnings.lines.empty()) << warnings.all();

  const amcr::PrototypeMemory second = load(&warnings);
  EXPECT_EQ(second.cacheCounts().read, 3u);
  EXPECT_EQ(second.cacheCounts().built, 0u);
  EXPECT_EQ(second.cacheCounts().written, 0u);
  EXPECT_TRUE(warnings.lines.empty()) << warnings.all();
  expectSameTables(second, freshBuild());
  expectSameTables(first, second);
  // What the filter reads, beyond the bytes: the same lookups.
  EXPECT_EQ(second[0].distance(40, 40, 7), first[0].distance(40, 40, 7));
  EXPECT_EQ(second[0].originalSize(), first[0].originalSize());
}

TEST_F(TableCacheTest, OneFilePerImageAndNoTemporaryFileLeft)
{
  load();
  load();
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(cache_))
    names.push_back(entry.path().filename().string());
  ASSERT_EQ(names.size(), 3u);
  for (const std::string& name : names)
    EXPECT_EQ(fs::path(name).extension(), ".table") << name;
}

TEST_F(TableCacheTest, TwoLoadsAtOnceLeaveSoundFiles)
{
  // Each writer renames a whole file of its own over the name: whichever
  // comes last, the file is whole.
  std::vector<std::thread> loads;
  std::vector<std::vector<std::string>> warnings(4);
  for (std::size_t k = 0; k < warnings.size(); ++k)
    loads.emplace_back([this, &warnings, k] {
      amcr::PrototypeMemory::loadDirectory(images_, params_,
                                           [&warnings, k](const std::string& w) { warnings[k].push_back(w); });
    });
  for (std::thread& t : loads)
    t.join();
  for (const auto& lines : warnings)
    EXPECT_TRUE(lines.empty()) << lines.front();
  Warnings after;
  const amcr::PrototypeMemory memory = load(&after);
  EXPECT_EQ(memory.cacheCounts().read, 3u);
  EXPECT_TRUE(after.lines.empty()) << after.all();
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(cache_))
    files += entry.path().extension() == ".table" ? 1 : 100;  // a temporary file counts 100
  EXPECT_EQ(files, 3u);
}

TEST_F(TableCacheTest, TruncatedFileIsRefusedAndRebuilt)
{
  expectRefusedAndRebuilt([](std::vector<char>& b) { b.resize(b.size() / 2); }, "truncated");
}

TEST_F(TableCacheTest, FileShorterThanItsHeaderIsRefusedAndRebuilt)
{
  expectRefusedAndRebuilt([](std::vector<char>& b) { b.resize(17); }, "truncated");
}

TEST_F(TableCacheTest, OnePayloadByteFlippedIsRefusedAndRebuilt)
{
  expectRefusedAndRebuilt([](std::vector<char>& b) { b[b.size() / 2] ^= 0x10; }, "checksum");
}

TEST_F(TableCacheTest, GarbageIsRefusedAndRebuilt)
{
  expectRefusedAndRebuilt(
      [](std::vector<char>& b) {
        for (std::size_t i = 0; i < b.size(); ++i)
          b[i] = static_cast<char>((i * 131 + 7) & 0xFF);
      },
      "wrong magic");
}

TEST_F(TableCacheTest, OtherFormatVersionIsRefusedAndRebuilt)
{
  expectRefusedAndRebuilt([](std::vector<char>& b) { b[8] = static_cast<char>(b[8] + 1); }, "format version");
}

TEST_F(TableCacheTest, FileForOtherParametersIsRefusedAsStaleAndRebuilt)
{
  // The file name depends on the image only: after a change of
  // prototype_size the same file is found, and its key tells it is stale.
  load();
  params_.prototype_size = 48;
  Warnings warnings;
  const amcr::PrototypeMemory memory = load(&warnings);
  EXPECT_EQ(memory.cacheCounts().refused, 3u);
  EXPECT_EQ(memory.cacheCounts().built, 3u);
  EXPECT_TRUE(warnings.mention(cacheFile("arrow"), "stale")) << warnings.all();
  expectSameTables(memory, freshBuild());
  EXPECT_EQ(load().cacheCounts().read, 3u);
}

// Compact tables and label directories go through the cache too:
// the instances keep their names, and a change of table_stride is stale.
TEST_F(TableCacheTest, CompactTablesOfInstancesAreReadBackAndAStrideChangeIsStale)
{
  fs::create_directory(images_ + "/kite");
  ASSERT_TRUE(cv::imwrite(images_ + "/kite/one.png", amcr_test::drawPrototype(ShapeId::kFlag)));
  params_.table_stride = 2;
  const amcr::PrototypeMemory first = load();
  ASSERT_EQ(first.size(), 4u);
  EXPECT_EQ(first.cacheCounts().written, 4u);
  const amcr::PrototypeMemory second = load();
  EXPECT_EQ(second.cacheCounts().read, 4u);
  expectSameTables(second, freshBuild());
  for (std::size_t i = 0; i < second.size(); ++i)
  {
    EXPECT_EQ(second[i].instance(), first[i].instance());
    EXPECT_EQ(second[i].tableStride(), 2);
  }
  EXPECT_EQ(second.findInstance("kite/one.png"), 2);  // by label: arrow, crescent, kite, star
  EXPECT_EQ(second[2].label(), "kite");

  params_.table_stride = 1;
  Warnings warnings;
  const amcr::PrototypeMemory exact = load(&warnings);
  EXPECT_EQ(exact.cacheCounts().refused, 4u);
  EXPECT_TRUE(warnings.mention(cacheFile("arrow"), "stale")) << warnings.all();
  EXPECT_EQ(exact[0].tableStride(), 1);
}

TEST_F(TableCacheTest, KeyOfAnotherImageIsRefusedAsStale)
{
  // A file copied under another image's name: its key is not this image's.
  load();
  const std::string arrow = cacheFile("arrow"), star = cacheFile("star");
  writeAll(arrow, readAll(star));
  Warnings warnings;
  const amcr::PrototypeMemory memory = load(&warnings);
  EXPECT_EQ(memory.cacheCounts().refused, 1u);
  EXPECT_TRUE(warnings.mention(arrow, "stale")) << warnings.all();
  expectSameTables(memory, freshBuild());
}

TEST_F(TableCacheTest, CacheThatCannotBeCreatedIsAWarningAndTheMemoryWorks)
{
  std::ofstream(root_.file("a_file")) << "not a directory";
  params_.table_cache_dir = root_.file("a_file") + "/tables";
  Warnings warnings;
  const amcr::PrototypeMemory memory = load(&warnings);
  EXPECT_EQ(memory.size(), 3u);
  EXPECT_EQ(memory.cacheCounts().built, 3u);
  EXPECT_EQ(memory.cacheCounts().written, 0u);
  EXPECT_TRUE(warnings.mention(params_.table_cache_dir, "cannot be used")) << warnings.all();
  EXPECT_EQ(warnings.lines.size(), 1u) << "one warning, not one per table:" << warnings.all();
  expectSameTables(memory, freshBuild());
}

TEST_F(TableCacheTest, ReadOnlyCacheIsAWarningAndStillRead)
{
  if (::geteuid() == 0)
    GTEST_SKIP() << "root writes to a read-only directory";
  load();
  fs::permissions(cache_, fs::perms::owner_read | fs::perms::owner_exec);
  Warnings warnings;
  const amcr::PrototypeMemory memory = load(&warnings);
  fs::permissions(cache_, fs::perms::owner_all);
  EXPECT_EQ(memory.cacheCounts().read, 3u);
  EXPECT_TRUE(warnings.mention(cache_, "cannot be written to")) << warnings.all();
  EXPECT_EQ(warnings.lines.size(), 1u) << warnings.all();
}

TEST_F(TableCacheTest, NoneTurnsTheCacheOff)
{
  params_.table_cache_dir = "none";
  EXPECT_EQ(load().cacheCounts().written, 0u);
  EXPECT_FALSE(fs::exists(cache_));
}

TEST_F(TableCacheTest, ParallelBuildGivesTheMemoryAndIndexOfOneThread)
{
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const amcr::PrototypeMemory one = freshBuild();
  const amcr::ProposalIndex one_index(one, 3);
  cv::setNumThreads(threads);
  const amcr::PrototypeMemory many = freshBuild();
  const amcr::ProposalIndex many_index(many, 3);
  expectSameTables(one, many);
  ASSERT_EQ(one_index.size(), many_index.size());
  const amcr::RaySignature rays = amcr_test::tableRays(one[1], one[1].width() / 2, one[1].height() / 2, 5, 1.f);
  amcr_test::expectSameCandidates(one_index.queryExact(rays, 20), many_index.queryExact(rays, 20));
}
}  // namespace
