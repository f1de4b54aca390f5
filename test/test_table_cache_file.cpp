// What a table cache file holds and how it is named: the prototype's bytes read back exactly and
// every damage to them refused, the cache key that changes with the image and the table's
// parameters only, and the content hash that any changed byte changes.
#include <cstdint>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/content_hash.h"
#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/memory/table_cache.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

// Behind the checksum, the payload is checked on its own: bytes that pass
// a checksum by chance, or were written by a faulty build, give an error,
// never a read past the end.
TEST(PrototypeBytes, RoundTripAndEveryDamageIsAMemoryError)
{
  const amcr::Prototype prototype("star", amcr_test::drawPrototype(ShapeId::kStar), 48, 40.0, 1.0);
  const std::vector<std::uint8_t> bytes = prototype.toBytes();
  const auto back = amcr::Prototype::fromBytes("star", bytes.data(), bytes.size());
  EXPECT_TRUE(back->toBytes() == bytes);
  EXPECT_EQ(back->label(), "star");
  EXPECT_EQ(back->interior().size(), prototype.interior().size());
  EXPECT_EQ(back->outline().size(), prototype.outline().size());

  for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 300)
    EXPECT_THROW(amcr::Prototype::fromBytes("star", bytes.data(), cut), amcr::MemoryError) << "cut at " << cut;
  std::vector<std::uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_THROW(amcr::Prototype::fromBytes("star", longer.data(), longer.size()), amcr::MemoryError);

  // The fields that size what follows: the stride (byte 16), the table's
  // width (20) and height (24), the kind (silhouette or template) right
  // after the mask, and the table's byte count after the two affines.
  const auto spoiled = [&](std::size_t at, std::int64_t value, std::size_t width) {
    std::vector<std::uint8_t> b = bytes;
    std::memcpy(b.data() + at, &value, width);
    return b;
  };
  const std::size_t kind_at = 28 + static_cast<std::size_t>(prototype.width() * prototype.height());
  const std::size_t table_count_at = kind_at + 4 + 96;
  for (const auto& b : {spoiled(16, 0, 4), spoiled(16, -5, 4), spoiled(20, 1 << 30, 4), spoiled(20, 4000, 4), spoiled(24, 0, 4),
                        spoiled(kind_at, 2, 4), spoiled(kind_at, -1, 4), spoiled(table_count_at, 12, 8),
                        spoiled(table_count_at, -1, 8)})
    EXPECT_THROW(amcr::Prototype::fromBytes("star", b.data(), b.size()), amcr::MemoryError);
  const std::size_t interior_count_at = table_count_at + 8 + prototype.tableBytes();
  const auto huge = spoiled(interior_count_at, std::int64_t(1) << 60, 8);
  EXPECT_THROW(amcr::Prototype::fromBytes("star", huge.data(), huge.size()), amcr::MemoryError);
  const auto outside = spoiled(interior_count_at + 8, 100000, 4);  // the first interior point's x
  EXPECT_THROW(amcr::Prototype::fromBytes("star", outside.data(), outside.size()), amcr::MemoryError);
}

TEST(TableCacheKey, ChangesWithTheImageAndEveryTableParameterOnly)
{
  const amcr::Params base;
  const std::uint64_t key = amcr::tableCacheKey(1, base);
  EXPECT_NE(amcr::tableCacheKey(2, base), key);
  amcr::Params p = base;
  p.prototype_size = 96;
  EXPECT_NE(amcr::tableCacheKey(1, p), key);
  p = base;
  p.edge_threshold = 41;
  EXPECT_NE(amcr::tableCacheKey(1, p), key);
  p = base;
  p.blur_sigma = 1.5;
  EXPECT_NE(amcr::tableCacheKey(1, p), key);
  p = base;
  p.edge_full_strength = 80;  // a template's edges follow it
  EXPECT_NE(amcr::tableCacheKey(1, p), key);
  p = base;
  p.table_stride = 2;
  EXPECT_NE(amcr::tableCacheKey(1, p), key);
  p = base;
  p.num_v_particles = 7;  // not a table parameter
  p.table_cache_dir = "/elsewhere";
  EXPECT_EQ(amcr::tableCacheKey(1, p), key);
}

TEST(ContentHash, EverySingleByteChangeChangesTheHash)
{
  std::vector<unsigned char> bytes(77);
  for (std::size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<unsigned char>(i * 37);
  const std::uint64_t hash = amcr::hashBytes(bytes.data(), bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i)
  {
    bytes[i] ^= 1;
    EXPECT_NE(amcr::hashBytes(bytes.data(), bytes.size()), hash) << "byte " << i;
    bytes[i] ^= 1;
  }
  EXPECT_NE(amcr::hashBytes(bytes.data(), bytes.size() - 1), hash);
}
}  // namespace
