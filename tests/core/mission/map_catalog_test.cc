#include "core/mission/map_catalog.h"

#include <fstream>

#include <gtest/gtest.h>

#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

void MakeMap(const std::string& path, const std::string& name, int frames, const std::string& state = "complete") {
  auto store = OpenTileStore(path, "png", true);
  store->SetMetadata("name", name);
  store->SetMetadata("format", "png");
  store->SetMetadata("bounds", "131.89,43.09,131.91,43.11");
  store->SetMetadata("minzoom", "20");
  store->SetMetadata("maxzoom", "24");
  store->SetMetadata("seamap_state", state);
  store->SetMetadata("seamap_layers", "raw,enhanced");
  store->PutTile({24, 1, 2}, {1, 2, 3});
  for (int i = 0; i < frames; ++i) {
    FrameRecord f;
    f.id = i;
    f.image = "f" + std::to_string(i) + ".jpg";
    f.time_s = 100.0 + i;
    store->Records().PutFrame(f);
  }
  store->Flush();
}

const CatalogEntry* Find(const std::vector<CatalogEntry>& entries, const std::string& id) {
  for (const auto& e : entries)
    if (e.id == id) return &e;
  return nullptr;
}

TEST(MapCatalog, ListsMapsAndFoldersWithTheirIndexAndBrokenFilesWithTheReason) {
  testing::TempDir dir;
  MakeMap((dir / "dive1.mbtiles").string(), "Dive one", 3);
  MakeMap((dir / "Dive 2 (north).mbtiles").string(), "Dive two", 0, "building");
  MakeMap((dir / "folder_map").string(), "As folder", 2);
  testing::WriteFile(dir / "broken.mbtiles", "this is not SQLite, just a half-copied file.....");
  testing::WriteFile(dir / "notes.txt", "not a map");
  std::filesystem::create_directories(dir / "photos");  // a folder without metadata.json

  MapCatalog catalog(dir.path().string());
  const auto entries = catalog.Scan();
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[0].id, "broken");  // sorted by id
  const CatalogEntry* one = Find(entries, "dive1");
  ASSERT_NE(one, nullptr);
  EXPECT_TRUE(one->available) << one->reason;
  EXPECT_EQ(one->name, "Dive one");
  EXPECT_EQ(one->state, "complete");
  EXPECT_EQ(one->frames, 3);
  EXPECT_EQ(one->first_time_s.value_or(-1), 100.0);
  EXPECT_EQ(one->last_time_s.value_or(-1), 102.0);
  ASSERT_TRUE(one->bounds.has_value());
  EXPECT_DOUBLE_EQ(one->bounds->north, 43.11);
  EXPECT_EQ(one->max_zoom, 24);
  EXPECT_EQ(one->layers, (std::vector<std::string>{"raw", "enhanced"}));
  EXPECT_GT(one->modified_unix_s, 1700000000);

  const CatalogEntry* two = Find(entries, "dive-2-north");
  ASSERT_NE(two, nullptr);
  EXPECT_TRUE(two->available) << two->reason;
  EXPECT_EQ(two->state, "interrupted");  // "building", but no process holds its lock
  const CatalogEntry* folder = Find(entries, "folder_map");
  ASSERT_NE(folder, nullptr);
  EXPECT_TRUE(folder->available) << folder->reason;
  EXPECT_EQ(folder->frames, 2);

  const CatalogEntry* broken = Find(entries, "broken");
  ASSERT_NE(broken, nullptr);
  EXPECT_FALSE(broken->available);
  EXPECT_NE(broken->reason.find("broken.mbtiles"), std::string::npos) << broken->reason;
}

TEST(MapCatalog, AMapIsBuildingWhileItsBuilderHoldsItsLock) {
  testing::TempDir dir;
  const std::string path = (dir / "dive.mbtiles").string();
  MakeMap(path, "Dive", 1, "building");
  MapCatalog catalog(dir.path().string());
  {
    MapLock lock = MapLock::Acquire(path, "--out");
    ASSERT_EQ(catalog.Scan().size(), 1u);
    EXPECT_EQ(catalog.Scan()[0].state, "building");
  }
  EXPECT_EQ(catalog.Scan()[0].state, "interrupted");
}

TEST(MapCatalog, SeesMapsAddedRemovedAndChangedWhileServing) {
  testing::TempDir dir;
  MakeMap((dir / "a.mbtiles").string(), "A", 1);
  MapCatalog catalog(dir.path().string());
  ASSERT_EQ(catalog.Scan().size(), 1u);

  MakeMap((dir / "b.mbtiles").string(), "B", 1);
  auto entries = catalog.Scan();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[1].name, "B");

  {
    auto store = OpenExistingMap((dir / "a.mbtiles").string(), true);
    store->SetMetadata("name", "A renamed");
    store->Flush();
  }
  std::filesystem::remove(dir / "b.mbtiles");
  entries = catalog.Scan();
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].name, "A renamed");

  // An empty finished map is listed, not served.
  { OpenTileStore((dir / "empty.mbtiles").string(), "png", true)->Flush(); }
  entries = catalog.Scan();
  const CatalogEntry* empty = Find(entries, "empty");
  ASSERT_NE(empty, nullptr);
  EXPECT_FALSE(empty->available);
  EXPECT_NE(empty->reason.find("no tiles"), std::string::npos) << empty->reason;
}

TEST(MapCatalog, IdsAreUrlSafeAndUnique) {
  EXPECT_EQ(CatalogId("Dive 12 (north).mbtiles"), "dive-12-north");
  EXPECT_EQ(CatalogId("survey_3.mbtiles"), "survey_3");
  EXPECT_EQ(CatalogId("(((.mbtiles"), "map");
  testing::TempDir dir;
  MakeMap((dir / "x.mbtiles").string(), "one", 0);
  MakeMap((dir / "X").string(), "two", 0);  // a folder of the same name
  const auto entries = MapCatalog(dir.path().string()).Scan();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_NE(entries[0].id, entries[1].id);
  EXPECT_THROW(MapCatalog((dir / "x.mbtiles").string()), InputError);
}

}  // namespace
}  // namespace seamap
