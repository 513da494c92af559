// The mission's height model as both store kinds keep it: read back exactly,
// replaced by a later one, shared by the layers, absent from a map without one.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

TerrainBlob Blob(const std::string& header, size_t bytes, uint8_t seed) {
  TerrainBlob b;
  b.header_json = header;
  for (size_t i = 0; i < bytes; ++i) b.cells.push_back(static_cast<uint8_t>(seed + i * 7));
  return b;
}

void ExpectSame(const TerrainBlob& a, const std::optional<TerrainBlob>& b) {
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(a.header_json, b->header_json);
  EXPECT_EQ(a.cells, b->cells);
}

TEST(TerrainRecords, MBTilesKeepsOneAndReadsItBackExactly) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  const TerrainBlob first = Blob(R"({"v":1})", 70000, 3), second = Blob(R"({"v":2})", 1234, 9);
  {
    MBTilesStore store(path);
    store.OpenLayer("relief");
    EXPECT_FALSE(store.Terrain().has_value());
    store.PutTerrain(first);
    ExpectSame(first, store.Terrain());
    store.PutTerrain(second);  // replaces
    store.Flush();
  }
  MBTilesStore read(path, MBTilesStore::Mode::kReadOnly);
  ExpectSame(second, read.Terrain());
  auto layer = read.OpenLayer("relief");
  ExpectSame(second, layer->Records().Terrain());
}

TEST(TerrainRecords, MBTilesWithoutTerrainHasNoTableAndSaysNone) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  { MBTilesStore store(path); }
  MBTilesStore read(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_FALSE(read.Terrain().has_value());
}

TEST(TerrainRecords, MBTilesLayerWritesTheMissionsTerrain) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  const TerrainBlob blob = Blob("{}", 10, 1);
  {
    MBTilesStore store(path);
    auto layer = store.OpenLayer("relief");
    layer->Records().PutTerrain(blob);
    layer->Flush();
  }
  MBTilesStore read(path, MBTilesStore::Mode::kReadOnly);
  ExpectSame(blob, read.Terrain());
}

TEST(TerrainRecords, FolderKeepsItInTwoFilesAndReadsItBack) {
  TempDir dir;
  const std::string root = (dir / "tiles").string();
  const TerrainBlob first = Blob(R"({"v":1})", 5000, 5), second = Blob(R"({"v":2})", 17, 2);
  {
    FolderStore store(root, "png");
    store.OpenLayer("relief");
    EXPECT_FALSE(store.Terrain().has_value());
    store.PutTerrain(first);
    store.PutTerrain(second);
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "tiles" / "terrain.json"));
  EXPECT_EQ(std::filesystem::file_size(dir / "tiles" / "terrain.bin"), 17u);
  FolderStore read(root, "png", FolderStore::Mode::kReadOnly);
  ExpectSame(second, read.Terrain());
  ExpectSame(second, read.OpenLayer("relief")->Records().Terrain());
  EXPECT_THROW(read.PutTerrain(first), std::runtime_error);
}

TEST(TerrainRecords, FolderWithHeaderButNoCellsIsAnErrorNamingTheFile) {
  TempDir dir;
  const std::string root = (dir / "tiles").string();
  {
    FolderStore store(root, "png");
    store.PutTerrain(Blob("{}", 4, 0));
  }
  std::filesystem::remove(dir / "tiles" / "terrain.bin");
  FolderStore read(root, "png", FolderStore::Mode::kReadOnly);
  try {
    read.Terrain();
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("terrain.bin"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
