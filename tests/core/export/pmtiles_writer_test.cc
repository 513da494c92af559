#include "core/export/pmtiles_writer.h"

#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

std::vector<uint8_t> ReadAll(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

uint64_t Le(const std::vector<uint8_t>& b, size_t at, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(b[at + i]) << (8 * i);
  return v;
}

std::vector<uint8_t> Slice(const std::vector<uint8_t>& b, uint64_t at, uint64_t n) {
  return {b.begin() + static_cast<long>(at), b.begin() + static_cast<long>(at + n)};
}

TEST(PmtilesWriter, WritesHeaderDirectoryAndDeduplicatedTiles) {
  testing::TempDir dir;
  const auto path = dir / "m.pmtiles";
  const std::vector<uint8_t> a(100, 'a'), b(50, 'b'), c(70, 'c');
  // In Hilbert order at z1: (0,0) (0,1) (1,1) (1,0); then z2 (0,0).
  PmtilesWriter w(path.string());
  w.Add({0, 0, 0}, c);
  w.Add({1, 0, 0}, a);
  w.Add({1, 0, 1}, a);  // a run with its neighbour
  w.Add({1, 1, 1}, b);
  w.Add({1, 1, 0}, a);                                       // a duplicate elsewhere: points back
  EXPECT_THROW(w.Add({1, 0, 0}, a), std::invalid_argument);  // out of order
  PmtilesArchiveInfo info;
  info.bounds = {-1.5, -2.25, 3.0, 4.0};
  info.center_zoom = 1;
  info.metadata_json = R"({"name":"m"})";
  const PmtilesSummary s = w.Finish(info);
  EXPECT_EQ(s.addressed_tiles, 5u);
  EXPECT_EQ(s.tile_entries, 4u);
  EXPECT_EQ(s.tile_contents, 3u);
  EXPECT_EQ(s.min_zoom, 0);
  EXPECT_EQ(s.max_zoom, 1);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tiles.tmp"));

  const auto f = ReadAll(path);
  ASSERT_EQ(f.size(), s.archive_bytes);
  EXPECT_EQ(std::string(f.begin(), f.begin() + 7), "PMTiles");
  EXPECT_EQ(f[7], 3);
  EXPECT_EQ(Le(f, 8, 8), 127u);                      // root right after the header
  EXPECT_EQ(Le(f, 56, 8) + Le(f, 64, 8), f.size());  // tile data last, to the end
  EXPECT_EQ(Le(f, 64, 8), 100u + 50 + 70);           // each blob once
  EXPECT_EQ(Le(f, 72, 8), 5u);
  EXPECT_EQ(f[96], 1);  // clustered
  EXPECT_EQ(f[97], 2);  // gzip directories
  EXPECT_EQ(f[99], 2);  // png
  EXPECT_EQ(static_cast<int32_t>(Le(f, 102, 4)), -15000000);
  EXPECT_EQ(static_cast<int32_t>(Le(f, 106, 4)), -22500000);
  const std::string meta = [&] {
    auto m = GunzipBytes(Slice(f, Le(f, 24, 8), Le(f, 32, 8)));
    return std::string(m.begin(), m.end());
  }();
  EXPECT_EQ(meta, R"({"name":"m"})");
  const auto root = DecodePmtilesDirectory(GunzipBytes(Slice(f, Le(f, 8, 8), Le(f, 16, 8))));
  ASSERT_EQ(root.size(), 4u);
  EXPECT_EQ(root[1].tile_id, 1u);
  EXPECT_EQ(root[1].run_length, 2u);
  EXPECT_EQ(root[3].tile_id, 4u);
  EXPECT_EQ(root[3].offset, root[1].offset);  // the duplicate
  EXPECT_EQ(Slice(f, Le(f, 56, 8) + root[2].offset, root[2].length), b);
}

TEST(PmtilesWriter, NamesAnUnwritableOutputAndLeavesNothingBehind) {
  testing::TempDir dir;
  try {
    PmtilesWriter w((dir / "missing" / "m.pmtiles").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing/m.pmtiles"), std::string::npos) << e.what();
  }
  {
    PmtilesWriter w((dir / "empty.pmtiles").string());
    EXPECT_THROW(w.Finish({}), std::invalid_argument);  // no tiles
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));  // unfinished archive and temp file removed
}

}  // namespace
}  // namespace seamap
