#include "core/mosaic/mission_recorder.h"

#include <gtest/gtest.h>

#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

PlacedFrame Rejected(int index, VehiclePose pose, std::optional<VehiclePose> nav_pose) {
  PlacedFrame p;
  p.spec.index = index;
  p.spec.image = "f" + std::to_string(index) + ".png";
  p.spec.pose = pose;
  p.spec.nav_pose = nav_pose;
  p.reject_reason = "too dark";
  return p;
}

TEST(MissionRecorder, KeepsTheNavigationsPoseBesideTheCorrectedOne) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  const LocalFrame frame(LatLon{43.1, 131.9});
  MissionRecorder recorder(&store, frame, MapDescription{});

  const VehiclePose placed{10, 20, 2.0, 35.0, 90.0, 1.0, -2.0};
  const VehiclePose nav{10.8, 19.4, 2.2, 35.5, 93.0, 1.5, -1.0};
  const auto [record, point] = recorder.Record(Rejected(0, placed, nav));

  const LatLon placed_ll = frame.ToLatLon({10, 20});
  const LatLon nav_ll = frame.ToLatLon({10.8, 19.4});
  EXPECT_DOUBLE_EQ(record.position.lat, placed_ll.lat);
  EXPECT_DOUBLE_EQ(record.heading_deg, 90.0);
  ASSERT_TRUE(record.nav.has_value());
  EXPECT_DOUBLE_EQ(record.nav->position.lat, nav_ll.lat);
  EXPECT_DOUBLE_EQ(record.nav->position.lon, nav_ll.lon);
  EXPECT_DOUBLE_EQ(record.nav->altitude_m, 2.2);
  EXPECT_DOUBLE_EQ(record.nav->depth_m, 35.5);
  EXPECT_DOUBLE_EQ(record.nav->heading_deg, 93.0);
  EXPECT_DOUBLE_EQ(record.nav->pitch_deg, 1.5);
  EXPECT_DOUBLE_EQ(record.nav->roll_deg, -1.0);
  EXPECT_DOUBLE_EQ(point.position.lon, placed_ll.lon);
  ASSERT_TRUE(point.nav.has_value());
  EXPECT_DOUBLE_EQ(point.nav->position.lat, nav_ll.lat);
  EXPECT_DOUBLE_EQ(point.nav->heading_deg, 93.0);

  const auto [plain, plain_point] = recorder.Record(Rejected(1, placed, std::nullopt));
  EXPECT_FALSE(plain.nav.has_value());
  EXPECT_FALSE(plain_point.nav.has_value());

  store.Flush();  // and the store has both
  ASSERT_EQ(store.Frames().size(), 2u);
  ASSERT_TRUE(store.Frames()[0].nav.has_value());
  EXPECT_DOUBLE_EQ(store.Frames()[0].nav->position.lon, nav_ll.lon);
  ASSERT_TRUE(store.Track()[0].nav.has_value());
  EXPECT_FALSE(store.Track()[1].nav.has_value());
}

}  // namespace
}  // namespace seamap
