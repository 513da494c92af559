// The recogniser's objects stored in the mission: the richer fields, and a
// new search that keeps what the operator decided.
#include "core/detect/detection_record.h"

#include <gtest/gtest.h>

#include "core/mission/mission_classes.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

RecognisedObject Object(const std::string& cls, double lat, double lon) {
  RecognisedObject o;
  o.class_name = cls;
  o.score = 0.8f;
  o.zoom = 23;
  o.levels = {25, 23};
  o.centre = {lat, lon};
  const double d = 0.000003;
  o.box = {LatLon{lat + d, lon - d}, LatLon{lat - d, lon - d}, LatLon{lat - d, lon + d}, LatLon{lat + d, lon + d},
           LatLon{lat + d, lon - d}};
  o.position_m = {1.5, -2.0};
  o.size_m = {0.5, 0.6};
  o.model = "seabed.onnx#0123456789abcdef";
  o.frames = {7, 3};
  o.time_s = 12.5;
  return o;
}

const Detection* Find(const std::vector<Detection>& all, const std::string& cls) {
  for (const Detection& d : all)
    if (d.class_name == cls) return &d;
  return nullptr;
}

TEST(StoreRecognised, KeepsTheBoxSizesFramesAndModel) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  StoreRecognised(store, {Object("tyre", 43.1, 131.9)}, "seabed.onnx#0123456789abcdef", {"tyre", "crate"});
  const auto all = store.Detections();
  ASSERT_EQ(all.size(), 1u);
  const Detection& d = all[0];
  EXPECT_EQ(d.source, "recogniser");
  EXPECT_EQ(d.model, "seabed.onnx#0123456789abcdef");
  EXPECT_EQ(d.status, "unconfirmed");
  EXPECT_EQ(d.level, 23);
  EXPECT_EQ(d.levels, (std::vector<int>{25, 23}));
  EXPECT_EQ(d.box.size(), 5u);
  ASSERT_TRUE(d.size_m && d.position_m);
  EXPECT_DOUBLE_EQ((*d.size_m)[1], 0.6);
  EXPECT_DOUBLE_EQ((*d.position_m)[0], 1.5);
  EXPECT_EQ(d.frames, (std::vector<int>{7, 3}));
  EXPECT_EQ(d.frame_id, 7);
  EXPECT_EQ(MissionClassTable(store), (std::vector<std::string>{"tyre", "crate"}));  // the model's names, in order
}

TEST(StoreRecognised, ASecondSearchKeepsTheOperatorsReviewAndOtherModels) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  const std::string model = "seabed.onnx#0123456789abcdef";
  StoreRecognised(store,
                  {Object("tyre", 43.1, 131.9), Object("crate", 43.1001, 131.9), Object("pipe", 43.1002, 131.9),
                   Object("rock", 43.1003, 131.9)},
                  model, {});
  Detection other = *Find(store.Detections(), "rock");  // another model's find, by hand
  other.id = 100;
  other.model = "wrecks.onnx#fedcba9876543210";
  store.PutDetection(other);
  auto all = store.Detections();
  Detection tyre = *Find(all, "tyre"), crate = *Find(all, "crate"), pipe = *Find(all, "pipe");
  tyre.status = "rejected";
  crate.status = "confirmed";
  store.PutDetection(tyre);
  store.PutDetection(crate);

  // Searched again (a newer model file): the tyre and the crate are found again, the pipe and the rock are not.
  StoreRecognised(store, {Object("tyre", 43.1, 131.9), Object("crate", 43.1001, 131.9)}, "seabed.onnx#1111111111111111",
                  {});
  all = store.Detections();
  ASSERT_TRUE(Find(all, "tyre"));
  EXPECT_EQ(Find(all, "tyre")->id, tyre.id);
  EXPECT_EQ(Find(all, "tyre")->status, "rejected");  // not recreated as a new, unreviewed find
  EXPECT_EQ(Find(all, "crate")->status, "confirmed");
  EXPECT_FALSE(Find(all, "pipe")) << "an unreviewed find the new search did not repeat stays";
  int rocks = 0;
  for (const Detection& d : all) rocks += d.class_name == "rock";
  EXPECT_EQ(rocks, 1) << "the other model's detection must stay, this model's unreviewed rock must go";
  EXPECT_EQ(Find(all, "rock")->model, "wrecks.onnx#fedcba9876543210");
}

}  // namespace
}  // namespace seamap
