// Detections and tile listings in both store kinds, and the ObservedStore
// decorator that announces committed tiles.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <set>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/observed_store.h"
#include "core/tiles/tile_version.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

std::vector<uint8_t> Bytes(const std::string& text) {
  return {text.begin(), text.end()};
}

Detection Mark(int64_t id, const std::string& cls) {
  Detection d;
  d.id = id;
  d.class_name = cls;
  d.score = 0.75;
  d.position = {43.1001, 131.9002};
  d.note = "note " + cls;
  d.source = id == 1 ? "recogniser" : "operator";
  d.status = id == 1 ? "rejected" : "confirmed";
  if (id == 1) {  // every recogniser field
    d.model = "tiles.onnx@0123abcd";
    d.level = 23;
    d.levels = {23, 21};
    d.box = {{43.1002, 131.9001}, {43.1000, 131.9001}, {43.1000, 131.9003}, {43.1002, 131.9003}, {43.1002, 131.9001}};
    d.position_m = std::array<double, 2>{12.25, -3.5};
    d.size_m = std::array<double, 2>{0.8, 0.6};
    d.frames = {12, 13, 40};
    d.frame_id = 12;
    d.time_s = 3.5;
    d.truncated = true;
    d.alt_class = "crate";
    d.sigma_m = 0.0123;  // a stereo object's uncertainty (any source stores it)
  }
  d.created = "2026-11-22T10:00:00Z";
  d.updated = "2026-11-22T10:05:00Z";
  d.seq = id * 10;
  return d;
}

void ExpectSame(const Detection& a, const Detection& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.class_name, b.class_name);
  EXPECT_DOUBLE_EQ(a.score, b.score);
  EXPECT_DOUBLE_EQ(a.position.lat, b.position.lat);
  EXPECT_DOUBLE_EQ(a.position.lon, b.position.lon);
  EXPECT_EQ(a.note, b.note);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.model, b.model);
  EXPECT_EQ(a.level, b.level);
  EXPECT_EQ(a.levels, b.levels);
  ASSERT_EQ(a.box.size(), b.box.size());
  for (size_t i = 0; i < a.box.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.box[i].lat, b.box[i].lat);
    EXPECT_DOUBLE_EQ(a.box[i].lon, b.box[i].lon);
  }
  EXPECT_EQ(a.position_m, b.position_m);
  EXPECT_EQ(a.size_m, b.size_m);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.truncated, b.truncated);
  EXPECT_EQ(a.alt_class, b.alt_class);
  EXPECT_EQ(a.sigma_m, b.sigma_m);
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.created, b.created);
  EXPECT_EQ(a.updated, b.updated);
  EXPECT_EQ(a.seq, b.seq);
}

// Runs the same checks on an MBTiles file and a folder.
class StoreKinds : public ::testing::TestWithParam<bool> {
 protected:
  std::string Path() const { return GetParam() ? (dir_ / "m.mbtiles").string() : (dir_ / "tiles").string(); }
  std::unique_ptr<TileStore> Open(bool create) const {
    if (GetParam())
      return std::make_unique<MBTilesStore>(Path(),
                                            create ? MBTilesStore::Mode::kCreate : MBTilesStore::Mode::kReadOnly);
    return std::make_unique<FolderStore>(Path(), "png",
                                         create ? FolderStore::Mode::kCreate : FolderStore::Mode::kReadOnly);
  }
  TempDir dir_;
};

TEST_P(StoreKinds, DetectionsSurviveReopeningWithEveryField) {
  {
    auto store = Open(true);
    store->Records().PutDetection(Mark(1, "tyre"));
    store->Records().PutDetection(Mark(2, "anchor"));
    Detection changed = Mark(2, "chain");
    store->Records().PutDetection(changed);  // replaces by id
    store->Records().PutDetection(Mark(3, "rock"));
    store->Records().DeleteDetection(3);
    store->Flush();
  }
  auto store = Open(false);
  auto all = store->Records().Detections();
  ASSERT_EQ(all.size(), 2u);
  ExpectSame(all[0], Mark(1, "tyre"));
  ExpectSame(all[1], Mark(2, "chain"));
}

TEST_P(StoreKinds, LayersShareTheMissionsDetections) {
  auto store = Open(true);
  auto layer = store->OpenLayer("enhanced");
  layer->Records().PutDetection(Mark(2, "chain"));
  store->Flush();
  ASSERT_EQ(store->Records().Detections().size(), 1u);
  EXPECT_EQ(layer->Records().Detections().size(), 1u);
}

TEST_P(StoreKinds, TileIdsListEveryTileOfTheLayerOnly) {
  auto store = Open(true);
  store->PutTile({3, 1, 2}, Bytes("a"));
  store->PutTile({20, 1000, 7}, Bytes("b"));
  auto layer = store->OpenLayer("enhanced");
  layer->PutTile({5, 4, 4}, Bytes("c"));
  store->Flush();
  auto ids = store->TileIds();
  std::set<std::tuple<int, int, int>> got;
  for (const auto& id : ids) got.insert({id.z, id.x, id.y});
  EXPECT_EQ(got, (std::set<std::tuple<int, int, int>>{{3, 1, 2}, {20, 1000, 7}}));
  auto layer_ids = layer->TileIds();
  ASSERT_EQ(layer_ids.size(), 1u);
  EXPECT_EQ(layer_ids[0].z, 5);
  EXPECT_EQ(layer_ids[0].x, 4);
  EXPECT_EQ(layer_ids[0].y, 4);
}

// A mission written before the recogniser's fields existed: one opened
// read-only reads them as absent, one opened to write gains the columns; a
// recogniser name kept in `source` moves to `model` either way.
TEST(MissionDetections, AFileWithTheOldSchemaOpensAndMigrates) {
  TempDir dir;
  const std::string path = (dir / "old.mbtiles").string();
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    const char* sql = R"sql(
CREATE TABLE metadata (name text, value text);
CREATE TABLE tiles (zoom_level integer, tile_column integer, tile_row integer, tile_data blob);
CREATE TABLE detections (id integer primary key, class text, score real, lat real, lon real, note text,
                         source text, frame_id integer, time_s real, created text, updated text, seq integer);
INSERT INTO detections VALUES (1, 'tyre', 0.9, 43.1, 131.9, '', 'yolo-tiles', 4, 2.5, 'c', 'u', 3);
INSERT INTO detections VALUES (2, 'wreck', 1.0, 43.2, 131.8, 'big', 'operator', NULL, NULL, 'c', 'u', 4);
)sql";
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  auto check = [](const std::vector<Detection>& all) {
    ASSERT_EQ(all.size(), 2u);
    EXPECT_EQ(all[0].source, "recogniser");
    EXPECT_EQ(all[0].model, "yolo-tiles");
    EXPECT_EQ(all[0].status, "unconfirmed");
    EXPECT_EQ(all[0].frame_id, 4);
    EXPECT_TRUE(all[0].box.empty());
    EXPECT_FALSE(all[0].position_m.has_value());
    EXPECT_EQ(all[1].source, "operator");
    EXPECT_EQ(all[1].model, "");
    EXPECT_EQ(all[1].status, "confirmed");
    EXPECT_EQ(all[1].note, "big");
  };
  check(MBTilesStore(path, MBTilesStore::Mode::kReadOnly).Detections());
  {
    MBTilesStore store(path);  // to write: columns added, the old row migrated
    check(store.Detections());
    Detection d = store.Detections()[0];
    d.status = "confirmed";
    d.size_m = std::array<double, 2>{0.5, 0.7};
    store.PutDetection(d);
    store.Flush();
  }
  auto all = MBTilesStore(path, MBTilesStore::Mode::kReadOnly).Detections();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].status, "confirmed");
  EXPECT_EQ(all[0].model, "yolo-tiles");
  EXPECT_EQ(all[0].size_m, (std::array<double, 2>{0.5, 0.7}));
}

INSTANTIATE_TEST_SUITE_P(MBTilesAndFolder, StoreKinds, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "MBTiles" : "Folder"; });

TEST(ObservedStore, AnnouncesTilesOnlyAfterTheFlushThatCommitsThem) {
  TempDir dir;
  MBTilesStore inner((dir / "m.mbtiles").string());
  std::vector<std::pair<std::string, CommittedTile>> heard;
  ObservedStore store(&inner, [&](const std::string& layer, const std::vector<CommittedTile>& tiles) {
    // By now another connection sees the tile.
    MBTilesStore reader((dir / "m.mbtiles").string(), MBTilesStore::Mode::kReadOnly);
    for (const auto& t : tiles) {
      auto bytes = layer.empty() ? reader.GetTile(t.id) : reader.OpenLayer(layer)->GetTile(t.id);
      EXPECT_TRUE(bytes.has_value());
      heard.push_back({layer, t});
    }
  });
  store.PutTile({4, 3, 2}, Bytes("first"));
  store.PutTile({4, 3, 3}, Bytes("second"));
  EXPECT_TRUE(heard.empty());
  store.Flush();
  ASSERT_EQ(heard.size(), 2u);
  EXPECT_EQ(heard[0].first, "");
  EXPECT_EQ(heard[0].second.version, TileVersion(Bytes("first")));
  EXPECT_EQ(heard[1].second.id.y, 3);

  auto layer = store.OpenLayer("enhanced");
  layer->PutTile({4, 3, 2}, Bytes("enhanced"));
  layer->Flush();
  ASSERT_EQ(heard.size(), 3u);
  EXPECT_EQ(heard[2].first, "enhanced");
  store.Flush();  // nothing new: nothing announced
  EXPECT_EQ(heard.size(), 3u);
}

TEST(ObservedStore, SharesTheInnerRecordsAndKeepsNoCheckpoints) {
  TempDir dir;
  MBTilesStore inner((dir / "m.mbtiles").string());
  ObservedStore store(&inner, nullptr);
  EXPECT_EQ(&store.Records(), static_cast<MissionRecords*>(&inner)) << "no forwarding copy";
  store.Records().PutDetection(Mark(4, "tyre"));
  ASSERT_EQ(inner.Detections().size(), 1u);
  // Rolling tiles back through it would change them unannounced.
  EXPECT_NE(inner.Checkpoints(), nullptr);
  EXPECT_EQ(store.Checkpoints(), nullptr);
  EXPECT_EQ(store.OpenLayer("enhanced")->Checkpoints(), nullptr);
  EXPECT_FALSE(ReadStoredCheckpoint(store));
}

TEST_P(StoreKinds, OnlyMBTilesKeepsCheckpoints) {
  auto store = Open(true);
  EXPECT_EQ(store->Checkpoints() != nullptr, GetParam());
  EXPECT_EQ(store->OpenLayer("enhanced")->Checkpoints() != nullptr, GetParam());
}

TEST(TileVersion, DependsOnEveryByteAndPrintsAsSixteenHexDigits) {
  const auto a = Bytes("a tile of some length, more than eight bytes");
  auto b = a;
  b[20] ^= 1;
  EXPECT_NE(TileVersion(a), TileVersion(b));
  EXPECT_NE(TileVersion(Bytes("ab")), TileVersion(Bytes("ba")));
  EXPECT_NE(TileVersion(Bytes("")), TileVersion(Bytes(std::string(1, '\0'))));
  EXPECT_EQ(TileVersion(a), TileVersion(Bytes("a tile of some length, more than eight bytes")));
  EXPECT_EQ(TileVersionHex(0x0123456789abcdefull), "0123456789abcdef");
  EXPECT_EQ(TileVersionHex(1), "0000000000000001");
}

}  // namespace
}  // namespace seamap
