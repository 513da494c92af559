// An operator's mark with a box (issue 32): stored like a recogniser's box,
// refused with the field named when malformed, and a new class joins the
// mission's class table.
#include "core/mission/operator_box.h"

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/mission/detection_book.h"
#include "core/mission/mission_classes.h"
#include "core/mission/truth_review.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const LatLon kCentre{43.1, 5.3};

nlohmann::json Ring(double w_m, double h_m, double east_m = 0, double north_m = 0) {
  const LocalFrame f(kCentre);
  const LatLon sw = f.ToLatLon({east_m - w_m / 2, north_m - h_m / 2}),
               ne = f.ToLatLon({east_m + w_m / 2, north_m + h_m / 2});
  return {{sw.lon, ne.lat}, {sw.lon, sw.lat}, {ne.lon, sw.lat}, {ne.lon, ne.lat}, {sw.lon, ne.lat}};
}

nlohmann::json Mark(const nlohmann::json& props) {
  return {{"type", "Feature"},
          {"geometry", {{"type", "Point"}, {"coordinates", {kCentre.lon, kCentre.lat}}}},
          {"properties", props}};
}

std::string FieldOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const DetectionError& e) {
    EXPECT_EQ(e.kind(), DetectionError::Kind::kInvalid) << e.what();
    return e.field();
  }
  return "(accepted)";
}

class OperatorBoxTest : public ::testing::Test {
 protected:
  testing::TempDir dir_;
  MBTilesStore store_{(dir_ / "m.mbtiles").string()};
};

TEST_F(OperatorBoxTest, AMarkKeepsItsBoxAndANewClassJoinsTheTable) {
  DetectionBook book(&store_);
  book.Load(store_);
  const Detection d = book.Create(Mark({{"class", "drum"}, {"box", Ring(0.9, 0.6)}}));
  ASSERT_EQ(d.box.size(), 5u);
  ASSERT_TRUE(d.size_m);
  EXPECT_NEAR((*d.size_m)[0], 0.9, 1e-3);
  EXPECT_NEAR((*d.size_m)[1], 0.6, 1e-3);
  EXPECT_EQ(d.status, "confirmed");
  // Stored: a new book reads it back, and the class table offers "drum" afterwards.
  DetectionBook again(&store_);
  again.Load(store_);
  const auto stored = again.Get(d.id);
  ASSERT_TRUE(stored);
  ASSERT_EQ(stored->box.size(), 5u);
  EXPECT_NEAR(stored->box[0].lat, d.box[0].lat, 1e-12);
  const auto classes = MissionClassTable(store_);
  EXPECT_NE(std::find(classes.begin(), classes.end(), "drum"), classes.end());

  // size_m alone: a box of that size around the point; null: a point mark again.
  const Detection sized = book.Update(d.id, {{"box", nullptr}, {"size_m", {0.5, 0.4}}});
  ASSERT_EQ(sized.box.size(), 5u);
  const LocalFrame f(kCentre);
  const LocalXY nw = f.FromLatLon(sized.box[0]), se = f.FromLatLon(sized.box[2]);
  EXPECT_NEAR(se.east - nw.east, 0.5, 1e-3);
  EXPECT_NEAR(nw.north - se.north, 0.4, 1e-3);
  const Detection point = book.Update(d.id, {{"box", nullptr}});
  EXPECT_TRUE(point.box.empty());
  EXPECT_FALSE(point.size_m);
}

TEST_F(OperatorBoxTest, BadBoxesAreRefusedNamingTheProperty) {
  DetectionBook book(&store_);
  book.Load(store_);
  auto create = [&](const nlohmann::json& props) { return [&book, props] { book.Create(Mark(props)); }; };
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", {{1, 2}, {3, 4}}}})), "properties.box");
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", "square"}})), "properties.box");
  nlohmann::json open = Ring(1, 1);
  open[4] = open[2];
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", open}})), "properties.box");
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", Ring(0, 1)}})), "properties.box") << "no area";
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", Ring(80, 1)}})), "properties.box") << "80 m";
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", Ring(1, 1, 5, 5)}})), "properties.box") << "point outside";
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"size_m", {-1, 1}}})), "properties.size_m");
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"size_m", {1}}})), "properties.size_m");
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", Ring(1, 1)}, {"size_m", {2, 1}}})), "properties.size_m");
  nlohmann::json nan_ring = Ring(1, 1);
  nan_ring[1][0] = 500.0;
  EXPECT_EQ(FieldOf(create({{"class", "drum"}, {"box", nan_ring}})), "properties.box");
  EXPECT_EQ(book.Query(DetectionFilter{}).size(), 0u) << "nothing stored";
}

TEST_F(OperatorBoxTest, TruthReviewConfirmsRejectsAndMarksTheMissed) {
  DetectionBook book(&store_);
  book.Load(store_);
  const LocalFrame f(kCentre);
  auto found = [&](const std::string& cls, double east_m) {
    Detection d;
    d.class_name = cls;
    d.model = "m.onnx#1";
    d.position = f.ToLatLon({east_m, 0});
    d.size_m = std::array<double, 2>{0.6, 0.6};
    return d;
  };
  book.Publish({found("tyre", 0.03), found("crate", 3.0), found("rock", 6.0)}, {{"tyre", "crate", "rock"}, ""});
  auto truth = [&](const std::string& cls, double east_m) {
    TruthObject t;
    t.class_name = cls;
    t.centre = f.ToLatLon({east_m, 0});
    const LatLon sw = f.ToLatLon({east_m - 0.3, -0.3}), ne = f.ToLatLon({east_m + 0.3, 0.3});
    t.west = sw.lon, t.south = sw.lat, t.east = ne.lon, t.north = ne.lat;
    t.size_m = 0.6;
    return t;
  };
  // The tyre is right, the "crate" is a drum, the rock is nothing, and a drum at 9 m was missed.
  const std::vector<TruthObject> objects = {truth("tyre", 0), truth("drum", 3.02), truth("drum", 9)};
  const TruthReviewResult r = ReviewAgainstTruth(book, objects);
  EXPECT_EQ(r.confirmed, 1);
  EXPECT_EQ(r.rejected, 2);
  EXPECT_EQ(r.added, 2);
  int drums_with_box = 0;
  for (const Detection& d : book.Query(DetectionFilter{})) {
    if (d.source == "recogniser") {
      EXPECT_EQ(d.status, d.class_name == "tyre" ? "confirmed" : "rejected");
    }
    if (d.source == "operator") drums_with_box += d.class_name == "drum" && d.box.size() == 5;
  }
  EXPECT_EQ(drums_with_box, 2);
  // Again: nothing changes, nothing is marked twice.
  const TruthReviewResult again = ReviewAgainstTruth(book, objects);
  EXPECT_EQ(again.added, 0);
  EXPECT_EQ(again.kept, 3);
}

}  // namespace
}  // namespace seamap
