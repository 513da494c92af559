#include <gtest/gtest.h>

#include <filesystem>

#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

void ExpectLayersAreSeparate(const std::string& path) {
  {
    auto store = OpenTileStore(path, "png", true);
    auto layer = store->OpenLayer("enhanced");
    store->PutTile({3, 1, 2}, {1, 2, 3});
    layer->PutTile({3, 1, 2}, {9, 9});
    layer->SetMetadata("maxzoom", "3");
    store->SetMetadata("maxzoom", "4");
    FrameRecord f;
    f.id = 7;
    store->Records().PutFrame(f);
    f.id = 8;
    layer->Records().PutFrame(f);  // dropped: the main map's builder records the frames
    layer->Records().PutTrackPoint({});
    layer->Flush();
    store->Flush();
    EXPECT_EQ(*store->GetTile({3, 1, 2}), (std::vector<uint8_t>{1, 2, 3}));
    EXPECT_EQ(*layer->GetTile({3, 1, 2}), (std::vector<uint8_t>{9, 9}));
    EXPECT_EQ(layer->TileCount(), 1);
    EXPECT_EQ(store->TileCount(), 1);
  }
  auto store = OpenTileStore(path, "png", false);  // reopened read-only
  auto layer = store->OpenLayer("enhanced");
  EXPECT_EQ(*layer->GetTile({3, 1, 2}), (std::vector<uint8_t>{9, 9}));
  EXPECT_FALSE(layer->GetTile({3, 0, 0}));
  EXPECT_EQ(layer->Metadata().at("maxzoom"), "3");
  EXPECT_EQ(store->Metadata().at("maxzoom"), "4");
  ASSERT_EQ(layer->Records().Frames().size(), 1u);  // the mission's frames
  EXPECT_EQ(layer->Records().Frames()[0].id, 7);
  EXPECT_EQ(store->Records().Frames().size(), 1u);
  EXPECT_TRUE(store->Records().Track().empty());
}

TEST(Layer, MBTilesKeepsLayersInOneFile) {
  testing::TempDir dir;
  ExpectLayersAreSeparate((dir / "m.mbtiles").string());
  EXPECT_FALSE(std::filesystem::exists(dir / "layers"));
}

TEST(Layer, FolderKeepsLayersInSubfolders) {
  testing::TempDir dir;
  ExpectLayersAreSeparate((dir / "tiles").string());
  EXPECT_TRUE(std::filesystem::exists(dir / "tiles/layers/enhanced/3/1/2.png"));
}

TEST(Layer, RejectsUnsafeNames) {
  testing::TempDir dir;
  auto store = OpenTileStore((dir / "m.mbtiles").string(), "png", true);
  EXPECT_THROW(store->OpenLayer("x; DROP TABLE tiles"), InputError);
  EXPECT_THROW(store->OpenLayer("../up"), InputError);
  EXPECT_THROW(store->OpenLayer(""), InputError);
}

}  // namespace
}  // namespace seamap
