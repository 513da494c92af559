// Issue 33, row 3: a detection stored with inf/NaN numbers (a recogniser
// before the fix stored a NaN box as JSON nulls and a NaN position as SQLite
// NULLs) is left out of ReadableDetections and named, so exports and packs
// of the rest go on; Detections() is unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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

}  // namespace
}  // namespace seamap
