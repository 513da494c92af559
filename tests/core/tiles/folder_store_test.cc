#include "core/tiles/folder_store.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

std::vector<uint8_t> Bytes(const std::string& text) {
  return {text.begin(), text.end()};
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

nlohmann::json ReadJson(const fs::path& path) {
  return nlohmann::json::parse(ReadText(path));
}

TEST(FolderStore, TileFilesFollowXyzLayout) {
  TempDir dir;
  const fs::path root = dir / "tiles";
  FolderStore store(root.string(), "png");
  store.PutTile({18, 134000, 95000}, Bytes("png bytes"));
  const fs::path file = root / "18" / "134000" / "95000.png";
  EXPECT_EQ(store.TilePath({18, 134000, 95000}), file);
  ASSERT_TRUE(fs::is_regular_file(file));  // written at once, XYZ row (not TMS)
  EXPECT_EQ(ReadText(file), "png bytes");
  EXPECT_EQ(*store.GetTile({18, 134000, 95000}), Bytes("png bytes"));
  EXPECT_FALSE(store.GetTile({18, 134000, 95001}).has_value());
}

TEST(FolderStore, ReplaceKeepsCountAndLeavesNoTempFiles) {
  TempDir dir;
  const fs::path root = dir / "t";
  FolderStore store(root.string(), "webp");
  store.PutTile({3, 1, 2}, Bytes("a"));
  store.PutTile({3, 1, 2}, Bytes("bb"));
  store.PutTile({3, 2, 2}, Bytes("c"));
  store.SetMetadata("name", "n");
  store.Flush();
  EXPECT_EQ(store.TileCount(), 2);
  EXPECT_EQ(*store.GetTile({3, 1, 2}), Bytes("bb"));
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    ++files;
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
  }
  EXPECT_EQ(files, 2 + 4);  // tiles + metadata.json, frames.json, track.json, detections.json
}

TEST(FolderStore, MetadataIsTileJson) {
  TempDir dir;
  const fs::path root = dir / "m";
  FolderStore store(root.string(), "jpg");
  store.SetMetadata("name", "dive 7");
  store.SetMetadata("format", "jpg");
  store.SetMetadata("bounds", "5.1,43.2,5.3,43.25");
  store.SetMetadata("center", "5.2,43.225,19");
  store.SetMetadata("minzoom", "14");
  store.SetMetadata("maxzoom", "21");
  store.SetMetadata("attribution", "SeaMap");
  store.Flush();
  const nlohmann::json j = ReadJson(root / "metadata.json");
  EXPECT_EQ(j.at("tilejson"), "3.0.0");
  EXPECT_EQ(j.at("tiles"), nlohmann::json::array({"{z}/{x}/{y}.jpg"}));
  EXPECT_EQ(j.at("name"), "dive 7");
  EXPECT_EQ(j.at("format"), "jpg");
  EXPECT_EQ(j.at("bounds"), nlohmann::json::array({5.1, 43.2, 5.3, 43.25}));
  EXPECT_EQ(j.at("center"), nlohmann::json::array({5.2, 43.225, 19}));
  EXPECT_EQ(j.at("minzoom"), 14);
  EXPECT_EQ(j.at("maxzoom"), 21);
  EXPECT_TRUE(j.at("minzoom").is_number_integer());
  EXPECT_EQ(j.at("attribution"), "SeaMap");
}

TEST(FolderStore, ReopenLoadsEverything) {
  TempDir dir;
  const fs::path root = dir / "r";
  FrameRecord frame;
  frame.id = 4;
  frame.image = "a.jpg";
  frame.time_s = 12.5;
  frame.position = {43.5, 5.5};
  frame.footprint = {LatLon{1, 2}, LatLon{3, 4}, LatLon{5, 6}, LatLon{7, 8}};
  frame.status = "used";
  {
    FolderStore store(root.string(), "png");
    store.PutTile({2, 1, 1}, Bytes("x"));
    store.PutTile({2, 1, 2}, Bytes("y"));
    store.SetMetadata("bounds", "-1.5,2,3,4.25");
    store.SetMetadata("minzoom", "2");
    store.PutFrame(frame);
    store.PutTrackPoint({0, std::nullopt, {43.0, 5.0}, 2.0, 40.0, 180.0, std::nullopt});
  }  // destructor flushes
  FolderStore store(root.string(), "png");
  EXPECT_EQ(store.TileCount(), 2);
  EXPECT_EQ(store.Metadata().at("bounds"), "-1.5,2,3,4.25");
  EXPECT_EQ(store.Metadata().at("minzoom"), "2");
  const auto frames = store.Frames();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].id, 4);
  EXPECT_EQ(frames[0].time_s, 12.5);
  EXPECT_DOUBLE_EQ(frames[0].footprint[3].lat, 7);
  EXPECT_DOUBLE_EQ(frames[0].footprint[3].lon, 8);
  const auto track = store.Track();
  ASSERT_EQ(track.size(), 1u);
  EXPECT_FALSE(track[0].time_s.has_value());
  EXPECT_DOUBLE_EQ(track[0].heading_deg, 180.0);
  // frames.json holds [lon,lat] footprints like the MBTiles frames table.
  EXPECT_EQ(ReadJson(root / "frames.json")[0].at("footprint")[0], nlohmann::json::array({2, 1}));
}

TEST(FolderStore, RecordsOnlyOnDiskAfterFlush) {
  TempDir dir;
  const fs::path root = dir / "f";
  FolderStore store(root.string(), "png");
  TrackPoint p;
  p.seq = 1;
  store.PutTrackPoint(p);
  EXPECT_EQ(ReadJson(root / "track.json").size(), 0u);
  store.Flush();
  EXPECT_EQ(ReadJson(root / "track.json").size(), 1u);
}

TEST(FolderStore, UncreatableFolderIsInputError) {
  TempDir dir;
  const fs::path file = testing::WriteFile(dir / "plain.txt", "not a folder");
  const std::string root = (file / "tiles").string();
  try {
    FolderStore store(root, "png");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), root);
    EXPECT_EQ(e.field(), "--out");
  }
}

TEST(FolderStore, ReadOnlyMode) {
  TempDir dir;
  EXPECT_THROW(FolderStore((dir / "missing").string(), "png", FolderStore::Mode::kReadOnly), InputError);
  { FolderStore((dir / "ro").string(), "png").PutTile({0, 0, 0}, Bytes("z")); }
  FolderStore store((dir / "ro").string(), "png", FolderStore::Mode::kReadOnly);
  EXPECT_EQ(store.TileCount(), 1);
  EXPECT_EQ(*store.GetTile({0, 0, 0}), Bytes("z"));
  EXPECT_THROW(store.PutTile({0, 0, 0}, Bytes("no")), std::runtime_error);
}

TEST(FolderStore, InvalidMetadataJsonNamesTheFile) {
  TempDir dir;
  testing::WriteFile(dir / "bad" / "metadata.json", "{ not json");
  try {
    FolderStore store((dir / "bad").string(), "png");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "bad" / "metadata.json").string());
  }
}

TEST(OpenTileStore, DispatchesOnSuffix) {
  TempDir dir;
  auto mb = OpenTileStore((dir / "a.mbtiles").string(), "png", true);
  EXPECT_NE(dynamic_cast<MBTilesStore*>(mb.get()), nullptr);
  auto folder = OpenTileStore((dir / "pyramid").string(), "jpg", true);
  auto* fs_store = dynamic_cast<FolderStore*>(folder.get());
  ASSERT_NE(fs_store, nullptr);
  EXPECT_EQ(fs_store->TilePath({1, 0, 1}), dir / "pyramid" / "1" / "0" / "1.jpg");
  EXPECT_THROW(OpenTileStore((dir / "none.mbtiles").string(), "png", false), InputError);
}

}  // namespace
}  // namespace seamap
