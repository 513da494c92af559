#include "core/export/pmtiles_directory.h"

#include <random>
#include <set>

#include <gtest/gtest.h>

namespace seamap {
namespace {

TEST(PmtilesTileId, MatchesTheSpecExamples) {
  // The spec's ids: z0 is 0; z1 goes (0,0) (0,1) (1,1) (1,0) along the curve.
  EXPECT_EQ(PmtilesTileId({0, 0, 0}), 0u);
  EXPECT_EQ(PmtilesTileId({1, 0, 0}), 1u);
  EXPECT_EQ(PmtilesTileId({1, 0, 1}), 2u);
  EXPECT_EQ(PmtilesTileId({1, 1, 1}), 3u);
  EXPECT_EQ(PmtilesTileId({1, 1, 0}), 4u);
  EXPECT_EQ(PmtilesTileId({2, 0, 0}), 5u);
  EXPECT_EQ(PmtilesTileId({12, 3423, 1763}), 19078479u);  // spec test vector (reference reader's tests)
}

TEST(PmtilesTileId, IsABijectionWhoseNeighboursAreAdjacentTiles) {
  for (int z = 0; z <= 6; ++z) {
    const int n = 1 << z;
    std::set<uint64_t> ids;
    for (int x = 0; x < n; ++x)
      for (int y = 0; y < n; ++y) {
        const uint64_t id = PmtilesTileId({z, x, y});
        EXPECT_EQ(PmtilesTileFromId(id), (TileId{z, x, y}));
        ids.insert(id);
      }
    ASSERT_EQ(ids.size(), static_cast<size_t>(n) * n);
    EXPECT_EQ(*ids.begin(), PmtilesTileId({z, 0, 0}));
    EXPECT_EQ(*ids.rbegin() - *ids.begin() + 1, ids.size());      // contiguous per zoom
    for (uint64_t id = *ids.begin(); id < *ids.rbegin(); ++id) {  // a Hilbert curve steps to a neighbour
      const TileId a = PmtilesTileFromId(id), b = PmtilesTileFromId(id + 1);
      EXPECT_EQ(std::abs(a.x - b.x) + std::abs(a.y - b.y), 1) << z << " " << id;
    }
  }
  EXPECT_EQ(PmtilesTileFromId(PmtilesTileId({26, 12345678, 33554431})), (TileId{26, 12345678, 33554431}));
  EXPECT_THROW(PmtilesTileId({2, 4, 0}), std::invalid_argument);
  EXPECT_THROW(PmtilesTileId({32, 0, 0}), std::invalid_argument);
}

std::vector<PmtilesEntry> RandomEntries(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<PmtilesEntry> entries;
  uint64_t id = 100, offset = 0;
  for (size_t i = 0; i < n; ++i) {
    id += 1 + rng() % 40;
    const uint32_t length = 1 + rng() % 5000, run = 1 + (rng() % 10 == 0 ? rng() % 50 : 0);
    const bool reuse = i > 0 && rng() % 8 == 0;  // a duplicate points back
    entries.push_back({id, reuse ? entries[rng() % i].offset : offset, length, run});
    if (reuse)
      entries.back().length = entries[0].length;
    else
      offset += length;
    id += run - 1;
  }
  return entries;
}

bool Same(const PmtilesEntry& a, const PmtilesEntry& b) {
  return a.tile_id == b.tile_id && a.offset == b.offset && a.length == b.length && a.run_length == b.run_length;
}

TEST(PmtilesDirectory, EncodesAndDecodesEntries) {
  const auto entries = RandomEntries(3000, 7);
  const auto bytes = EncodePmtilesDirectory(entries);
  const auto back = DecodePmtilesDirectory(GunzipBytes(GzipBytes(bytes)));
  ASSERT_EQ(back.size(), entries.size());
  for (size_t i = 0; i < entries.size(); ++i) ASSERT_TRUE(Same(back[i], entries[i])) << i;
  // Contiguous blobs take one byte for the offset (0): the clustered layout's saving.
  EXPECT_EQ(EncodePmtilesDirectory({{5, 0, 10, 1}, {6, 10, 20, 1}}),
            (std::vector<uint8_t>{2, 5, 1, 1, 1, 10, 20, 1, 0}));
  EXPECT_THROW(DecodePmtilesDirectory({2, 5}), std::runtime_error);
}

TEST(PmtilesDirectory, SplitsIntoLeavesWhenTheRootWouldNotFit) {
  const auto entries = RandomEntries(20000, 11);
  const auto small = BuildPmtilesDirectories({entries.begin(), entries.begin() + 10}, 16384 - 127);
  EXPECT_EQ(small.leaf_count, 0u);
  EXPECT_TRUE(small.leaves.empty());

  const auto dirs = BuildPmtilesDirectories(entries, 16384 - 127, 1000);
  ASSERT_GT(dirs.leaf_count, 1u);
  EXPECT_LE(dirs.root.size(), 16384u - 127);
  const auto root = DecodePmtilesDirectory(GunzipBytes(dirs.root));
  ASSERT_EQ(root.size(), dirs.leaf_count);
  size_t next = 0;
  for (const auto& leaf_entry : root) {
    EXPECT_EQ(leaf_entry.run_length, 0u);  // a pointer to a leaf
    ASSERT_LE(leaf_entry.offset + leaf_entry.length, dirs.leaves.size());
    const auto leaf = DecodePmtilesDirectory(GunzipBytes(
        {dirs.leaves.begin() + leaf_entry.offset, dirs.leaves.begin() + leaf_entry.offset + leaf_entry.length}));
    ASSERT_FALSE(leaf.empty());
    EXPECT_EQ(leaf.front().tile_id, leaf_entry.tile_id);
    for (const auto& e : leaf) ASSERT_TRUE(Same(e, entries[next++]));
  }
  EXPECT_EQ(next, entries.size());
  EXPECT_THROW(BuildPmtilesDirectories({}, 100), std::invalid_argument);
}

}  // namespace
}  // namespace seamap
