// The proposal index's k-d tree in the table cache (index_cache.h): a second
// index over the same entries reads the tree back and answers every query as
// the built one does; a damaged, stale or foreign file is refused with the
// reason and the tree built again; the recognizer stores its tree where
// table_cache_dir says, and nowhere with "none".
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/filter/index_cache.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/recognizer.h"
#include "amcr/memory/table_cache.h"
#include "candidate_lists.h"
#include "scene_drawing.h"
#include "warning_lines.h"

namespace
{
namespace fs = std::filesystem;

constexpr int kStride = 6;  // the default index_stride

using Warnings = amcr_test::WarningLines;

std::vector<fs::path> treeFiles(const std::string& directory)
{
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(directory))
    if (entry.path().extension() == ".kdtree")
      files.push_back(entry.path());
  return files;
}

class IndexCacheTest : public ::testing::Test
{
protected:
  static void SetUpTestSuite() { memory_ = amcr_test::drawnMemory(amcr_test::allShapes()); }
  static void TearDownTestSuite() { memory_.reset(); }

  std::unique_ptr<amcr::ProposalIndex> index(Warnings& warnings) const
  {
    return std::make_unique<amcr::ProposalIndex>(*memory_, kStride, std::vector<bool>(), warnings.sink(), &cache_);
  }

  /// The only tree file of the cache.
  fs::path treeFile() const
  {
    const std::vector<fs::path> files = treeFiles(dir_.path());
    EXPECT_EQ(files.size(), 1u);
    return files.empty() ? fs::path() : files.front();
  }

  /// Whether `a` and `b` answer 300 scans taken from the tables alike.
  static void expectSameAnswers(const amcr::ProposalIndex& a, const amcr::ProposalIndex& b)
  {
    std::mt19937_64 gen(11);
    int compared = 0;
    for (int trial = 0; trial < 300; ++trial)
    {
      const amcr::Prototype& prototype = (*memory_)[gen() % memory_->size()];
      const cv::Point at = prototype.interior()[gen() % prototype.interior().size()];
      const int bin = static_cast<int>(gen() % amcr::kDirectionBins);
      const amcr::RaySignature rays = amcr_test::tableRays(prototype, at.x, at.y, bin, 1.3f);
      const std::vector<amcr::ProposalCandidate> ca = a.query(rays, 64), cb = b.query(rays, 64);
      amcr_test::expectSameCandidates(ca, cb);
      compared += ca.empty() ? 0 : 1;
    }
    EXPECT_GT(compared, 100);  // most scans see an edge on all 8 rays
  }

  /// A damaged file is refused with `reason` and the tree built again and
  /// stored sound: the next index reads it.
  void expectRefusedAndRebuilt(const std::string& reason)
  {
    Warnings refused;
    const auto rebuilt = index(refused);
    EXPECT_FALSE(rebuilt->treeFromCache());
    EXPECT_TRUE(refused.mention("was refused")) << reason;
    EXPECT_TRUE(refused.mention(reason));
    Warnings none;
    const auto read = index(none);
    EXPECT_TRUE(read->treeFromCache());
    EXPECT_TRUE(none.lines.empty());
    expectSameAnswers(*rebuilt, *read);
  }

  static std::shared_ptr<const amcr::PrototypeMemory> memory_;
  amcr_test::TempDir dir_;
  amcr::TableCache cache_{dir_.path()};
};
std::shared_ptr<const amcr::PrototypeMemory> IndexCacheTest::memory_;

TEST_F(IndexCacheTest, SecondIndexReadsTheTreeAndAnswersAsTheBuiltOne)
{
  Warnings w;
  const auto built = index(w);
  EXPECT_FALSE(built->treeFromCache());
  ASSERT_EQ(treeFiles(dir_.path()).size(), 1u);
  const auto read = index(w);
  EXPECT_TRUE(read->treeFromCache());
  EXPECT_TRUE(w.lines.empty());
  EXPECT_EQ(read->size(), built->size());
  expectSameAnswers(*built, *read);
  for (const auto& entry : fs::directory_iterator(dir_.path()))  // no temporary file left
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
}

TEST_F(IndexCacheTest, OnePayloadByteFlippedIsRefusedAndRebuilt)
{
  Warnings w;
  index(w);
  const fs::path file = treeFile();
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(static_cast<std::streamoff>(fs::file_size(file) / 2));
  f.put('\x5a');
  f.close();
  expectRefusedAndRebuilt("checksum");
}

TEST_F(IndexCacheTest, TruncatedFileIsRefusedAndRebuilt)
{
  Warnings w;
  index(w);
  const fs::path file = treeFile();
  fs::resize_file(file, fs::file_size(file) - 100);
  expectRefusedAndRebuilt("truncated");
}

TEST_F(IndexCacheTest, TreeOfOtherEntriesIsRefusedAsStale)
{
  // The file of another memory's tree under this tree's name.
  const auto other_memory = amcr_test::drawnMemory({amcr_test::ShapeId::kStar, amcr_test::ShapeId::kArrow});
  Warnings w;
  amcr::ProposalIndex(*other_memory, kStride, {}, w.sink(), &cache_);
  const fs::path other = treeFile();
  index(w);
  std::vector<fs::path> files = treeFiles(dir_.path());
  ASSERT_EQ(files.size(), 2u);
  const fs::path mine = files[0] == other ? files[1] : files[0];
  fs::copy_file(other, mine, fs::copy_options::overwrite_existing);
  fs::remove(other);
  expectRefusedAndRebuilt("stale");
}

TEST_F(IndexCacheTest, KeyFollowsTheEntriesAndTheLeafSize)
{
  cv::Mat a(50, amcr::kFeatureRays, CV_32F);
  cv::randu(a, -1.f, 1.f);
  cv::Mat b = a.clone();
  b.at<float>(49, 7) += 1e-6f;
  EXPECT_EQ(amcr::indexCacheKey(a, 10), amcr::indexCacheKey(a.clone(), 10));
  EXPECT_NE(amcr::indexCacheKey(a, 10), amcr::indexCacheKey(b, 10));
  EXPECT_NE(amcr::indexCacheKey(a, 10), amcr::indexCacheKey(a, 11));
  EXPECT_NE(amcr::indexCacheKey(a, 10), amcr::indexCacheKey(a.rowRange(0, 49), 10));
}

TEST_F(IndexCacheTest, RecognizerStoresItsTreeWhereTableCacheDirSaysAndNowhereWithNone)
{
  amcr::Params params;
  params.table_cache_dir = dir_.path();
  amcr::Recognizer first(params, memory_);
  EXPECT_EQ(treeFiles(dir_.path()).size(), 1u);
  amcr::Recognizer second(params, memory_);
  EXPECT_EQ(treeFiles(dir_.path()).size(), 1u);

  // "none": no file here nor in the default directory (this binary's own ROS_HOME).
  const std::string default_dir = amcr::tableCacheDirectory("");
  ASSERT_FALSE(default_dir.empty());
  fs::create_directories(default_dir);
  const std::size_t before = treeFiles(default_dir).size();
  params.table_cache_dir = "none";
  amcr::Recognizer uncached(params, memory_);
  EXPECT_EQ(treeFiles(dir_.path()).size(), 1u);
  EXPECT_EQ(treeFiles(default_dir).size(), before);
}
}  // namespace
