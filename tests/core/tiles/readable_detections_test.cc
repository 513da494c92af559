// Issue 33, row 3: a detection stored with inf/NaN numbers (a recogniser
// before the fix stored a NaN box as JSON nulls and a NaN position as SQLite
// NULLs) is left out of ReadableDetections and named, so exports and packs
// of the rest go on; Detections() is unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/tiles/folder_store.h"
#include "core/tiles/layer_records.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

Detection Found(int64_t id) {
  Detection d;
  d.id = id;
  d.class_name = "tyre";
  d.score = 0.9;
  d.position = {43.1, 131.9};
  d.source = "recogniser";
  d.box = {{43.1, 131.9}, {43.1, 131.91}, {43.11, 131.91}, {43.11, 131.9}, {43.1, 131.9}};
  d.position_m = std::array<double, 2>{1.0, 2.0};
  return d;
}

TEST(ReadableDetections, NonFiniteRecordsAreLeftOutAndNamed) {
  testing::TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  {
    MBTilesStore store(path);
    store.PutDetection(Found(1));
    Detection nan_box = Found(2);
    for (LatLon& c : nan_box.box) c = {nan, nan};
    nan_box.position = {nan, nan};
    store.PutDetection(nan_box);
    Detection inf_size = Found(3);
    inf_size.size_m = std::array<double, 2>{inf, 1.0};
    store.PutDetection(inf_size);
    store.PutDetection(Found(4));
    store.Flush();
  }
  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  // The server's reader skips them and counts them; the export's names them.
  EXPECT_EQ(store.Detections().size(), 2u);
  EXPECT_EQ(store.SkippedDetections(), 2);
  std::vector<int64_t> unreadable;
  const std::vector<Detection> readable = store.ReadableDetections(&unreadable);
  ASSERT_EQ(readable.size(), 2u);
  EXPECT_EQ(readable[0].id, 1);
  EXPECT_EQ(readable[1].id, 4);
  EXPECT_EQ(unreadable, (std::vector<int64_t>{2, 3}));
  // Through a layer's view of the mission, the same.
  MBTilesStore writable(path);
  LayerRecords layer(&writable.Records());
  unreadable.clear();
  EXPECT_EQ(layer.ReadableDetections(&unreadable).size(), 2u);
  EXPECT_EQ(unreadable.size(), 2u);
  EXPECT_FALSE(IsFiniteDetection([&] {
    Detection d = Found(5);
    d.score = nan;
    return d;
  }()));
  EXPECT_TRUE(IsFiniteDetection(Found(6)));
}

TEST(ReadableDetections, AFolderMapWithABrokenRecordOpensKeepsItAndNamesIt) {
  testing::TempDir dir;
  const std::filesystem::path root = dir / "map";
  {
    FolderStore store(root.string(), "png");
    store.PutDetection(Found(1));
  }  // flushed: detections.json holds one good record
  // A search before the fix wrote a NaN box and position as nulls.
  nlohmann::json records = nlohmann::json::parse(std::ifstream(root / "detections.json"));
  nlohmann::json broken = records[0];
  broken["id"] = 7;
  broken["box"] = nlohmann::json::parse("[[null, 1]]");
  records.push_back(broken);
  std::ofstream(root / "detections.json") << records.dump();
  {
    FolderStore store(root.string(), "png", FolderStore::Mode::kReadOnly);  // used to throw
    ASSERT_EQ(store.Detections().size(), 1u);
    EXPECT_EQ(store.SkippedDetections(), 1);
    std::vector<int64_t> unreadable;
    EXPECT_EQ(store.ReadableDetections(&unreadable).size(), 1u);
    EXPECT_EQ(unreadable, (std::vector<int64_t>{7}));
  }
  {
    FolderStore store(root.string(), "png");  // written again: the broken record is not dropped
    store.PutDetection(Found(2));
  }
  const nlohmann::json after = nlohmann::json::parse(std::ifstream(root / "detections.json"));
  ASSERT_EQ(after.size(), 3u);
  EXPECT_EQ(after[2], broken);
}

}  // namespace
}  // namespace seamap
