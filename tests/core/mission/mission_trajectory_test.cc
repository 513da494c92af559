// The mission's trajectory: which one its frames were placed with, and both
// it and the navigation's as poses, from a real MBTiles mission.
#include "core/mission/mission_trajectory.h"

#include <gtest/gtest.h>

#include "core/mission/mission_metadata.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

FrameRecord Frame(int id, double time_s, double lat, std::optional<double> nav_lat) {
  FrameRecord f;
  f.id = id;
  f.image = "img_" + std::to_string(id) + ".png";
  f.time_s = time_s;
  f.position = {lat, 5.0};
  f.depth_m = 20 + id, f.altitude_m = 2, f.heading_deg = 10 * id, f.pitch_deg = 1, f.roll_deg = -1;
  f.status = "used";
  if (nav_lat) {
    NavigatedPose& n = f.nav.emplace();
    n.position = {*nav_lat, 5.0};
    n.depth_m = 30 + id, n.heading_deg = 90;
  }
  return f;
}

TEST(MissionTrajectory, TheSourceFollowsTheRecordedModeOrTheFrames) {
  EXPECT_EQ(PlacedTrajectorySource(nlohmann::json{{"mode", "refine"}}, true), TrajectorySource::kRefined);
  EXPECT_EQ(PlacedTrajectorySource(nlohmann::json{{"mode", "vo"}}, true), TrajectorySource::kEstimated);
  EXPECT_EQ(PlacedTrajectorySource(nlohmann::json{{"mode", "ekf"}}, false), TrajectorySource::kEstimated);
  EXPECT_EQ(PlacedTrajectorySource(std::nullopt, true), TrajectorySource::kEstimated);  // corrected, mode unknown
  EXPECT_EQ(PlacedTrajectorySource(std::nullopt, false), TrajectorySource::kNav);
  EXPECT_EQ(PlacedTrajectorySource(nlohmann::json("refine"), false), TrajectorySource::kNav);  // not an object
  EXPECT_STREQ(TrajectorySourceName(TrajectorySource::kRefined), "refined");
  EXPECT_STREQ(TrajectorySourceName(TrajectorySource::kEstimated), "estimated");
  EXPECT_STREQ(TrajectorySourceName(TrajectorySource::kNav), "nav");
}

TEST(MissionTrajectory, ARefinedMissionHoldsTheRefinedAndTheNavigationsPoses) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  store.Records().PutFrame(Frame(0, 100, 43.0, 43.1));
  store.Records().PutFrame(Frame(1, 101, 43.2, std::nullopt));  // refine left it where the navigation had it
  MissionMetadata m;
  m.trajectory = nlohmann::json{{"mode", "refine"}, {"pairs", 3}};
  WriteMissionMetadata(&store, m);
  store.Flush();

  const MissionTrajectory t = MissionTrajectory::Read(store);
  EXPECT_EQ(t.placed(), TrajectorySource::kRefined);
  EXPECT_TRUE(t.Has(TrajectorySource::kRefined));
  EXPECT_TRUE(t.Has(TrajectorySource::kNav));
  EXPECT_FALSE(t.Has(TrajectorySource::kEstimated));
  EXPECT_EQ(t.HeldText(), "refined, nav");
  EXPECT_TRUE(t.Poses(TrajectorySource::kEstimated).empty());

  const auto refined = t.Poses(TrajectorySource::kRefined);
  ASSERT_EQ(refined.size(), 2u);
  EXPECT_EQ(refined[0].position.lat, 43.0);
  EXPECT_EQ(refined[0].depth_m, 20);
  EXPECT_EQ(refined[1].image, "img_1.png");
  EXPECT_EQ(refined[1].time_s, 101);
  EXPECT_EQ(refined[1].heading_deg, 10);
  const auto nav = t.Poses(TrajectorySource::kNav);
  ASSERT_EQ(nav.size(), 2u);
  EXPECT_EQ(nav[0].position.lat, 43.1);
  EXPECT_EQ(nav[0].depth_m, 30);
  EXPECT_EQ(nav[0].heading_deg, 90);
  EXPECT_EQ(nav[1].position.lat, 43.2);  // no navigation's pose kept: the placed one was it
}

TEST(MissionTrajectory, AnUncorrectedMissionHoldsOnlyTheNavigation) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  store.Records().PutFrame(Frame(0, 100, 43.0, std::nullopt));
  store.Flush();
  const MissionTrajectory t = MissionTrajectory::Read(store);
  EXPECT_EQ(t.placed(), TrajectorySource::kNav);
  EXPECT_EQ(t.HeldText(), "nav");
  EXPECT_FALSE(t.Has(TrajectorySource::kRefined));
  EXPECT_EQ(t.Poses(TrajectorySource::kNav).size(), 1u);
}

}  // namespace
}  // namespace seamap
