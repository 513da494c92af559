#include "server/tile_source.h"

#include <atomic>
#include <thread>

#include <gtest/gtest.h>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using test::Png;
using test::QuotedVersion;
using test::Text;

class TileSourceTest : public ::testing::Test {
 protected:
  seamap::testing::TempDir dir_;
  test::TestMission mission_ = test::WriteTestMission(dir_.path());
};

TEST_F(TileSourceTest, ServesTheStoredBytesWithTheirVersionAsStrongEtag) {
  TileSource source(mission_.path.string(), 2);
  for (const auto& [id, bytes] : mission_.tiles) {
    auto tile = source.Get("", id);
    ASSERT_TRUE(tile) << id.z << "/" << id.x << "/" << id.y;
    EXPECT_EQ(*tile->bytes, Text(bytes));
    EXPECT_EQ(tile->etag, QuotedVersion(bytes));
    EXPECT_EQ(tile->etag.size(), 18u);
  }
}

TEST_F(TileSourceTest, MissingTileIsNullopt) {
  TileSource source(mission_.path.string(), 1);
  EXPECT_FALSE(source.Get("", TileId{3, 5, 5}));
  EXPECT_FALSE(source.Get("enhanced", TileId{3, 4, 3}));
}

TEST_F(TileSourceTest, ServesLayerTilesApartFromTheMainMap) {
  TileSource source(mission_.path.string(), 2);
  auto enhanced = source.Get("enhanced", TileId{3, 4, 2});
  auto raw = source.Get("", TileId{3, 4, 2});
  ASSERT_TRUE(enhanced);
  ASSERT_TRUE(raw);
  EXPECT_EQ(*enhanced->bytes, Text(mission_.enhanced.at(TileId{3, 4, 2})));
  EXPECT_NE(enhanced->etag, raw->etag);
}

// Regression: a layer request read the layer list (metadata) while holding
// the only reader, and metadata needs a reader too: it waited forever.
TEST_F(TileSourceTest, ALayerRequestWithOneReaderDoesNotWaitForItself) {
  TileSource source(mission_.path.string(), 1);
  EXPECT_TRUE(source.Get("enhanced", TileId{3, 4, 2}));
  EXPECT_FALSE(source.Get("enhanced", TileId{3, 4, 3}));
}

TEST_F(TileSourceTest, UnknownLayerThrowsOutOfRange) {
  TileSource source(mission_.path.string(), 1);
  EXPECT_THROW(source.Get("nope", TileId{3, 4, 2}), std::out_of_range);
  // The main layer's own name is not a sub-layer.
  EXPECT_THROW(source.Get("raw", TileId{3, 4, 2}), std::out_of_range);
  // The reader went back to the pool: the next request does not block.
  EXPECT_TRUE(source.Get("", TileId{3, 4, 2}));
}

TEST_F(TileSourceTest, LayersFormatAndMetadata) {
  TileSource source(mission_.path.string(), 1);
  EXPECT_EQ(source.Layers(), (std::vector<std::string>{"raw", "enhanced"}));
  EXPECT_EQ(source.Format(), "png");
  EXPECT_TRUE(source.IsLayer("enhanced"));
  EXPECT_FALSE(source.IsLayer("raw"));
  EXPECT_FALSE(source.IsLayer("nope"));

  auto main = source.Metadata("");
  EXPECT_EQ(main.at("name"), "Test mission");
  EXPECT_EQ(main.at("bounds"), "4.999,42.999,5.011,43.011");
  auto layer = source.Metadata("enhanced");
  EXPECT_EQ(layer.at("name"), "Test mission (enhanced)");
  EXPECT_EQ(layer.at("minzoom"), "15");
  EXPECT_EQ(layer.count("seamap_layers"), 0u) << "a layer's metadata holds only its own keys";
}

TEST_F(TileSourceTest, WithoutLayerListTheMainMapIsRaw) {
  const auto path = dir_ / "plain.mbtiles";
  {
    MBTilesStore store(path.string());
    store.PutTile(TileId{1, 0, 0}, Png(8, 8, 1));
    store.Flush();
  }
  TileSource source(path.string(), 1);
  EXPECT_EQ(source.Layers(), std::vector<std::string>{"raw"});
  EXPECT_EQ(source.Format(), "png");
  EXPECT_FALSE(source.IsLayer("enhanced"));
}

TEST_F(TileSourceTest, CachesTilesUntilInvalidated) {
  TileSource source(mission_.path.string(), 2);
  const TileId id{3, 4, 2};
  const auto before = source.Get("", id);
  ASSERT_TRUE(before);

  MBTilesStore writer(mission_.path.string());
  const auto replaced = Png(16, 16, 99);
  writer.PutTile(id, replaced);
  writer.Flush();
  // Still the cached tile: nobody said it changed.
  EXPECT_EQ(source.Get("", id)->etag, before->etag);

  source.Invalidate("", id);
  auto after = source.Get("", id);
  ASSERT_TRUE(after);
  EXPECT_EQ(*after->bytes, Text(replaced));
  EXPECT_EQ(after->etag, QuotedVersion(replaced));
}

TEST_F(TileSourceTest, InvalidatingOneLayerKeepsTheOther) {
  TileSource source(mission_.path.string(), 1);
  const TileId id{3, 4, 2};
  const auto raw = source.Get("", id);
  const auto enhanced = source.Get("enhanced", id);
  MBTilesStore writer(mission_.path.string());
  writer.PutTile(id, Png(16, 16, 77));
  writer.OpenLayer("enhanced")->PutTile(id, Png(16, 16, 78));
  writer.Flush();
  source.Invalidate("enhanced", id);
  EXPECT_EQ(source.Get("", id)->etag, raw->etag);
  EXPECT_EQ(*source.Get("enhanced", id)->bytes, Text(Png(16, 16, 78)));
}

TEST_F(TileSourceTest, AnExternalWriterMakesCachedTilesExpire) {
  TileSource source(mission_.path.string(), 1);
  source.SetExternalWriter(true);
  const TileId id{3, 4, 3};
  ASSERT_TRUE(source.Get("", id));
  const auto replaced = Png(16, 16, 123);
  {
    MBTilesStore writer(mission_.path.string());
    writer.PutTile(id, replaced);
    writer.Flush();
  }
  // No Invalidate: the new tile shows once the cached one has expired (about a second).
  bool seen = false;
  for (int i = 0; i < 300 && !seen; ++i) {
    seen = *source.Get("", id)->bytes == Text(replaced);
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(seen);
}

TEST_F(TileSourceTest, TheCacheHoldsNoMoreThanItsCap) {
  const auto path = dir_ / "many.mbtiles";
  const auto old_bytes = [](int i) { return std::vector<uint8_t>(100, static_cast<uint8_t>(i)); };
  const auto new_bytes = [](int i) { return std::vector<uint8_t>(100, static_cast<uint8_t>(i + 100)); };
  constexpr int kTiles = 100;
  {
    MBTilesStore store(path.string());
    for (int i = 0; i < kTiles; ++i) store.PutTile(TileId{7, i, 0}, old_bytes(i));
    store.Flush();
  }
  constexpr size_t kCap = 6400;  // room for at most 64 tiles of 100 bytes
  TileSource source(path.string(), 1, kCap);
  for (int i = 0; i < kTiles; ++i) ASSERT_TRUE(source.Get("", TileId{7, i, 0}));
  {
    MBTilesStore writer(path.string());
    for (int i = 0; i < kTiles; ++i) writer.PutTile(TileId{7, i, 0}, new_bytes(i));
    writer.Flush();
  }
  // Without Invalidate, a tile still cached is the old one; every other one is read again.
  int fresh = 0;
  for (int i = 0; i < kTiles; ++i) {
    auto tile = source.Get("", TileId{7, i, 0});
    ASSERT_TRUE(tile);
    const bool is_new = *tile->bytes == Text(new_bytes(i));
    EXPECT_TRUE(is_new || *tile->bytes == Text(old_bytes(i))) << i;
    EXPECT_EQ(tile->etag, QuotedVersion(is_new ? new_bytes(i) : old_bytes(i))) << i;
    fresh += is_new;
  }
  EXPECT_GE(fresh, kTiles - int(kCap / 100));
}

TEST_F(TileSourceTest, ParallelReadersAllGetTheirTiles) {
  TileSource source(mission_.path.string(), 2, 0);  // no cache: every Get reads the file
  std::atomic<int> good{0}, bad{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 50; ++i) {
        const auto& [id, bytes] = *std::next(mission_.tiles.begin(), (t + i) % mission_.tiles.size());
        auto tile = source.Get("", id);
        (tile && *tile->bytes == Text(bytes) ? good : bad)++;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(good.load(), 400);
  EXPECT_EQ(bad.load(), 0);
}

TEST_F(TileSourceTest, ReadsAFolderPyramid) {
  const auto folder = dir_ / "pyramid";
  const auto jpg = std::vector<uint8_t>{0xff, 0xd8, 0xff, 0xe0, 1, 2, 3};
  {
    FolderStore store(folder.string(), "jpg");
    store.PutTile(TileId{4, 3, 2}, jpg);
    store.SetMetadata("name", "Folder mission");
    store.SetMetadata("format", "jpg");
    store.Flush();
  }
  TileSource source(folder.string(), 4);
  EXPECT_EQ(source.Format(), "jpg");
  EXPECT_EQ(source.Metadata("").at("name"), "Folder mission");
  auto tile = source.Get("", TileId{4, 3, 2});
  ASSERT_TRUE(tile);
  EXPECT_EQ(*tile->bytes, Text(jpg));
  EXPECT_EQ(tile->etag, QuotedVersion(jpg));
  EXPECT_FALSE(source.Get("", TileId{4, 3, 3}));
}

TEST_F(TileSourceTest, NotATileMapThrowsInputErrorNamingThePath) {
  const auto missing = (dir_ / "missing.mbtiles").string();
  try {
    TileSource source(missing, 1);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.mbtiles"), std::string::npos) << e.what();
  }
}

TEST_F(TileSourceTest, LiveMetadataComesFromTheWritingStore) {
  MBTilesStore live(mission_.path.string());
  live.SetMetadata("name", "Renamed while building");  // not committed: only the live store knows
  TileSource source(mission_.path.string(), 1, 64u << 20, &live);
  EXPECT_EQ(source.Metadata("").at("name"), "Renamed while building");
  EXPECT_EQ(source.Layers(), (std::vector<std::string>{"raw", "enhanced"}));
}

}  // namespace
}  // namespace seamap::server
