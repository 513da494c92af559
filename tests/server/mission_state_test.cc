#include "server/mission_state.h"

#include <gtest/gtest.h>

#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using test::MakeFrame;

TrackPoint Point(int seq, double lat = 43, double lon = 5) {
  TrackPoint p;
  p.seq = seq;
  p.time_s = seq * 1.5;
  p.position = {lat, lon};
  return p;
}

std::vector<int> Ids(const std::vector<FrameRecord>& frames) {
  std::vector<int> ids;
  for (const auto& f : frames) ids.push_back(f.id);
  return ids;
}

TEST(MissionState, BuoyTrackNumberedInOrderAndServedFromASeq) {
  MissionState mission;
  EXPECT_EQ(mission.BuoyTrackSize(), 0);
  std::vector<TrackPoint> fixes(5);
  for (int i = 0; i < 5; ++i) fixes[i].position = {51.0 + i * 1e-5, 13.6}, fixes[i].time_s = 100.0 + i;
  mission.SetBuoyTrack(fixes);
  EXPECT_EQ(mission.BuoyTrackSize(), 5);
  const auto tail = mission.BuoyTrackFrom(3);
  ASSERT_EQ(tail.size(), 2u);
  EXPECT_EQ(tail[0].seq, 3);
  EXPECT_DOUBLE_EQ(tail[1].position.lat, 51.0 + 4e-5);
  EXPECT_TRUE(mission.BuoyTrackFrom(5).empty());
  EXPECT_EQ(mission.TrackSize(), 0);  // the vehicle's track is apart
}

TEST(FootprintContains, AxisAlignedSquare) {
  const auto fp = MakeFrame(0, {43, 5}, 0.001, "used", "").footprint;
  EXPECT_TRUE(FootprintContains(fp, {43, 5}));
  EXPECT_TRUE(FootprintContains(fp, {43.0009, 4.9991}));
  EXPECT_FALSE(FootprintContains(fp, {43.0011, 5}));
  EXPECT_FALSE(FootprintContains(fp, {43, 5.0011}));
  EXPECT_FALSE(FootprintContains(fp, {42.9989, 4.9989}));
}

TEST(FootprintContains, RotatedFootprintExcludesTheBoundingBoxCorners) {
  // A diamond (camera turned 45 degrees): its bounding box's corners are outside.
  const std::array<LatLon, 4> diamond = {LatLon{43.001, 5.0}, LatLon{43.0, 5.001}, LatLon{42.999, 5.0},
                                         LatLon{43.0, 4.999}};
  EXPECT_TRUE(FootprintContains(diamond, {43, 5}));
  EXPECT_TRUE(FootprintContains(diamond, {43.0004, 5.0004}));
  EXPECT_FALSE(FootprintContains(diamond, {43.0009, 5.0009}));
  EXPECT_FALSE(FootprintContains(diamond, {42.9991, 4.9991}));
}

TEST(FootprintContains, WorksInEitherWindingOrder) {
  auto fp = MakeFrame(0, {-12, -150}, 0.0005, "used", "").footprint;
  std::reverse(fp.begin(), fp.end());
  EXPECT_TRUE(FootprintContains(fp, {-12.0001, -150.0001}));
  EXPECT_FALSE(FootprintContains(fp, {-12.001, -150}));
}

TEST(MissionState, LoadsFramesTrackAndMetadataFromTheStore) {
  seamap::testing::TempDir dir;
  const auto mission = test::WriteTestMission(dir.path());
  MBTilesStore store(mission.path.string(), MBTilesStore::Mode::kReadOnly);
  MissionState state;
  state.Load(store);

  const auto status = state.StatusJson();
  EXPECT_EQ(status["name"], "Test mission");
  EXPECT_EQ(status["state"], "complete");
  EXPECT_EQ(status["format"], "png");
  EXPECT_EQ(status["frames_done"], 4);
  EXPECT_EQ(status["frames_total"], 4);
  EXPECT_EQ(status["frames_rejected"], 1);
  EXPECT_DOUBLE_EQ(status["progress"].get<double>(), 1.0);
  EXPECT_EQ(status["origin"], nlohmann::json::array({43.0, 5.0}));
  EXPECT_EQ(status["last_pose"]["frame"], 3);
  EXPECT_EQ(state.TrackSize(), 5);
  ASSERT_TRUE(state.Frame(1));
  EXPECT_EQ(state.Frame(1)->image, "frame_1.jpg");
  EXPECT_FALSE(state.Frame(7));
}

TEST(MissionState, AStoppedBuildIsReportedAsStopped) {
  seamap::testing::TempDir dir;
  const auto mission = test::WriteTestMission(dir.path());
  {
    MBTilesStore store(mission.path.string());
    store.SetMetadata("seamap_state", "building");  // a build that did not finish
  }
  MBTilesStore store(mission.path.string(), MBTilesStore::Mode::kReadOnly);
  MissionState state;
  state.Load(store);
  EXPECT_EQ(state.StatusJson()["state"], "stopped");
}

TEST(MissionState, StatusSaysHowTheTrajectoryWasEstimated) {
  seamap::testing::TempDir dir;
  const auto mission = test::WriteTestMission(dir.path());
  {
    MBTilesStore store(mission.path.string());
    store.SetMetadata("seamap_trajectory", R"({"mode":"refine","registered_cross_line":812,"nav_only_frames":0})");
  }
  MBTilesStore store(mission.path.string(), MBTilesStore::Mode::kReadOnly);
  MissionState state;
  state.Load(store);
  const auto status = state.StatusJson();
  EXPECT_EQ(status["trajectory"]["mode"], "refine");
  EXPECT_EQ(status["trajectory"]["registered_cross_line"], 812);
  MissionState plain;
  EXPECT_TRUE(plain.StatusJson()["trajectory"].is_null());
}

TEST(MissionState, StatusOfAnEmptyMission) {
  MissionState state;
  const auto status = state.StatusJson();
  EXPECT_TRUE(status["progress"].is_null()) << "unknown total: no progress fraction";
  EXPECT_TRUE(status["last_pose"].is_null());
  EXPECT_TRUE(status["origin"].is_null());
  EXPECT_EQ(status["layers"], nlohmann::json::array({"raw"}));
  EXPECT_EQ(status["replay"], false);
  EXPECT_EQ(state.TrackSize(), 0);
  EXPECT_TRUE(state.TrackFrom(0).empty());
}

TEST(MissionState, SettersShowInTheStatus) {
  MissionState state;
  state.SetName("Harbour survey");
  state.SetReplay(true);
  state.SetLayers({"raw", "enhanced"}, "webp");
  state.SetOrigin(-33.5, 151.25);
  Progress p;
  p.state = "building";
  p.frames_done = 30;
  p.frames_total = 120;
  p.frames_rejected = 2;
  p.tiles_written = 400;
  p.frames_per_s = 2.5;
  state.SetProgress(p);

  const auto status = state.StatusJson();
  EXPECT_EQ(status["name"], "Harbour survey");
  EXPECT_EQ(status["replay"], true);
  EXPECT_EQ(status["layers"], nlohmann::json::array({"raw", "enhanced"}));
  EXPECT_EQ(status["format"], "webp");
  EXPECT_EQ(status["origin"], nlohmann::json::array({-33.5, 151.25}));
  EXPECT_EQ(status["state"], "building");
  EXPECT_EQ(status["frames_done"], 30);
  EXPECT_EQ(status["frames_rejected"], 2);
  EXPECT_EQ(status["tiles_written"], 400);
  EXPECT_DOUBLE_EQ(status["frames_per_s"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(status["progress"].get<double>(), 0.25);
  EXPECT_EQ(state.progress().frames_total, 120);
}

TEST(MissionState, ProgressNeverExceedsOne) {
  MissionState state;
  Progress p;
  p.frames_done = 12;
  p.frames_total = 10;
  state.SetProgress(p);
  EXPECT_DOUBLE_EQ(state.StatusJson()["progress"].get<double>(), 1.0);
}

TEST(MissionState, LastPoseIsTheLatestUsedFrame) {
  MissionState state;
  state.AddFrame(MakeFrame(0, {43, 5}, 0.0002, "used", "a.png"), Point(0));
  state.AddFrame(MakeFrame(1, {43.1, 5.1}, 0.0002, "blurred", "b.png"), Point(1));
  const auto pose = state.StatusJson()["last_pose"];
  EXPECT_EQ(pose["frame"], 0);
  EXPECT_DOUBLE_EQ(pose["lat"].get<double>(), 43.0);
  EXPECT_DOUBLE_EQ(pose["lon"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(pose["depth_m"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(pose["altitude_m"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(pose["heading_deg"].get<double>(), 90.0);
  EXPECT_DOUBLE_EQ(pose["time_s"].get<double>(), 0.0);
}

TEST(MissionState, TrackFromReturnsPointsFromTheSequenceNumberOn) {
  MissionState state;
  for (int i = 0; i < 6; ++i) state.AddFrame(MakeFrame(i, {43, 5}, 0.0002, "used", ""), Point(i, 43 + i * 0.001));
  EXPECT_EQ(state.TrackSize(), 6);
  auto from3 = state.TrackFrom(3);
  ASSERT_EQ(from3.size(), 3u);
  EXPECT_EQ(from3.front().seq, 3);
  EXPECT_DOUBLE_EQ(from3.front().position.lat, 43.003);
  EXPECT_EQ(from3.back().seq, 5);
  EXPECT_EQ(state.TrackFrom(0).size(), 6u);
  EXPECT_EQ(state.TrackFrom(-5).size(), 6u);
  EXPECT_TRUE(state.TrackFrom(6).empty());
  EXPECT_TRUE(state.TrackFrom(100).empty());
}

TEST(MissionState, TrackWithGapsCountsFromTheLastSequenceNumber) {
  MissionState state;
  state.AddFrame(MakeFrame(0, {43, 5}, 0.0002, "used", ""), Point(0));
  state.AddFrame(MakeFrame(1, {43, 5}, 0.0002, "used", ""), Point(4));
  EXPECT_EQ(state.TrackSize(), 5);
  auto from2 = state.TrackFrom(2);
  ASSERT_EQ(from2.size(), 1u);
  EXPECT_EQ(from2[0].seq, 4);
}

TEST(MissionState, AFramePaintedAgainReplacesItsRecordAndKeepsTheTrack) {
  MissionState state;
  state.AddFrame(MakeFrame(0, {43, 5}, 0.0002, "used", "a.png"), Point(0));
  state.AddFrame(MakeFrame(2, {43, 5}, 0.0002, "used", "c.png"), Point(1));
  state.AddFrame(MakeFrame(1, {43, 5}, 0.0002, "used", "b.png"), Point(1));   // inserted in id order
  state.AddFrame(MakeFrame(2, {43, 5}, 0.0002, "used", "c2.png"), Point(0));  // replaced
  ASSERT_TRUE(state.Frame(1));
  EXPECT_EQ(state.Frame(1)->image, "b.png");
  EXPECT_EQ(state.Frame(2)->image, "c2.png");
  EXPECT_EQ(state.TrackSize(), 2) << "older track points are not appended again";
  EXPECT_EQ(Ids(state.FramesCovering({43, 5}, 10)).size(), 3u);
}

TEST(MissionState, FramesCoveringSortsByFootprintCentreDistance) {
  MissionState state;
  // All three cover (43, 5); their centres are 0.0003, 0.0001 and 0.0002 away.
  state.AddFrame(MakeFrame(0, {43.0003, 5.0}, 0.0005, "used", ""), Point(0));
  state.AddFrame(MakeFrame(1, {43.0, 5.0001}, 0.0005, "used", ""), Point(1));
  state.AddFrame(MakeFrame(2, {42.9998, 5.0}, 0.0005, "used", ""), Point(2));
  state.AddFrame(MakeFrame(3, {43.0, 5.0}, 0.0005, "overexposed", ""), Point(3));  // rejected: never listed
  state.AddFrame(MakeFrame(4, {43.01, 5.0}, 0.0005, "used", ""), Point(4));        // elsewhere
  EXPECT_EQ(Ids(state.FramesCovering({43, 5}, 10)), (std::vector<int>{1, 2, 0}));
  EXPECT_EQ(Ids(state.FramesCovering({43, 5}, 2)), (std::vector<int>{1, 2}));
  EXPECT_EQ(Ids(state.FramesCovering({43.01, 5}, 10)), std::vector<int>{4});
  EXPECT_TRUE(state.FramesCovering({44, 6}, 10).empty());
}

TEST(MissionState, FramesCoveringWeighsLongitudeByLatitude) {
  MissionState state;
  // At 60 degrees a degree of longitude is half a degree of latitude: frame 0
  // (0.00015 deg east = 0.000075 "north" units) is nearer than frame 1 (0.0001 north).
  state.AddFrame(MakeFrame(0, {60.0, 10.00015}, 0.0005, "used", ""), Point(0));
  state.AddFrame(MakeFrame(1, {60.0001, 10.0}, 0.0005, "used", ""), Point(1));
  EXPECT_EQ(Ids(state.FramesCovering({60, 10}, 10)), (std::vector<int>{0, 1}));
}

TEST(FrameJson, HasPoseFootprintInLonLatOrderAndImageUrls) {
  const auto f = MakeFrame(7, {43, 5}, 0.001, "used", "/data/img_0007.tif");
  const auto j = FrameJson(f);
  EXPECT_EQ(j["id"], 7);
  EXPECT_EQ(j["image"], "img_0007.tif");
  EXPECT_DOUBLE_EQ(j["time_s"].get<double>(), 70.0);
  EXPECT_DOUBLE_EQ(j["lat"].get<double>(), 43.0);
  EXPECT_DOUBLE_EQ(j["lon"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(j["pitch_deg"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(j["roll_deg"].get<double>(), -1.0);
  EXPECT_DOUBLE_EQ(j["depth_m"].get<double>(), 37.0);
  ASSERT_EQ(j["footprint"].size(), 4u);
  EXPECT_DOUBLE_EQ(j["footprint"][0][0].get<double>(), 4.999);   // lon first
  EXPECT_DOUBLE_EQ(j["footprint"][0][1].get<double>(), 43.001);  // then lat
  EXPECT_EQ(j["image_url"], "/api/frames/7/image");
  EXPECT_EQ(j["thumb_url"], "/api/frames/7/image?max=256");
  EXPECT_FALSE(j.contains("image_path")) << "the server's file paths stay private";

  FrameRecord untimed = f;
  untimed.time_s.reset();
  EXPECT_TRUE(FrameJson(untimed)["time_s"].is_null());
  EXPECT_TRUE(PoseJson(untimed)["time_s"].is_null());
}

}  // namespace
}  // namespace seamap::server
