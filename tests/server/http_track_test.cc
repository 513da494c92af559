// GET /api/track?source=estimated|nav, the frames' nav pose and the status's
// trajectory_corrected, for a mission with and without a corrected trajectory.
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

// The test mission's track (43 + 0.00005 i, 5 + 0.00005 i) as if corrected:
// the navigation had each point 0.0001 deg further north-east; frames 0 and 1 likewise.
void CorrectTheTestMission(const std::filesystem::path& path) {
  MBTilesStore store(path.string());
  for (auto f : store.Frames()) {
    if (f.id > 1) continue;
    f.nav = NavigatedPose{{f.position.lat + 0.0001, f.position.lon + 0.0001}, 2.4, 30.5, 97, 0.5, -0.5};
    store.PutFrame(f);
  }
  for (auto p : store.Track()) {
    p.nav = NavigatedPosition{{p.position.lat + 0.0001, p.position.lon + 0.0001}, 97};
    store.PutTrackPoint(p);
  }
}

TEST_F(HttpServerTest, WithoutCorrectionTheNavTrackIsTheSameTrack) {
  Start();
  const json estimated = GetJson("/api/track");
  const json nav = GetJson("/api/track?source=nav");
  EXPECT_EQ(estimated["properties"]["source"], "estimated");
  EXPECT_EQ(estimated["properties"]["corrected"], false);
  EXPECT_EQ(nav["properties"]["source"], "nav");
  EXPECT_EQ(nav["properties"]["corrected"], false);
  EXPECT_EQ(nav["geometry"], estimated["geometry"]);
  EXPECT_EQ(GetJson("/api/track?source=estimated")["geometry"], estimated["geometry"]);
  const json status = GetJson("/api/status");
  EXPECT_EQ(status["trajectory_corrected"], false);
  EXPECT_EQ(status["corrected_frames"], 0);
  EXPECT_TRUE(GetJson("/api/frames/0")["nav"].is_null());
}

TEST_F(HttpServerTest, UnknownTrackSourceIsABadRequestNamingTheParameter) {
  Start();
  ExpectError(Get("/api/track?source=raw"), 400, "parameter 'source'", "unknown source");
  ExpectError(Get("/api/track?source="), 400, "parameter 'source'", "empty source");
  ExpectError(Get("/api/track?source=nav&since=x"), 400, "since", "bad since with a good source");
}

TEST_F(HttpServerTest, CorrectedMissionServesBothTracks) {
  CorrectTheTestMission(mission_.path);
  Start();
  const json estimated = GetJson("/api/track?source=estimated");
  const json nav = GetJson("/api/track?source=nav");
  EXPECT_EQ(estimated["properties"]["corrected"], true);
  EXPECT_EQ(nav["properties"]["corrected"], true);
  ASSERT_EQ(nav["geometry"]["coordinates"].size(), 5u);
  ASSERT_EQ(estimated["geometry"]["coordinates"].size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(estimated["geometry"]["coordinates"][i][1].get<double>(), 43.0 + 0.00005 * i, 1e-9);
    EXPECT_NEAR(nav["geometry"]["coordinates"][i][1].get<double>(), 43.0001 + 0.00005 * i, 1e-9);
    EXPECT_NEAR(nav["geometry"]["coordinates"][i][0].get<double>(), 5.0001 + 0.00005 * i, 1e-9);
  }
  EXPECT_EQ(nav["properties"]["times"], estimated["properties"]["times"]);

  const json nav_since3 = GetJson("/api/track?source=nav&since=3");  // `since` as before
  EXPECT_EQ(nav_since3["properties"]["from"], 2);
  EXPECT_EQ(nav_since3["properties"]["next"], 5);
  ASSERT_EQ(nav_since3["geometry"]["coordinates"].size(), 3u);
  EXPECT_NEAR(nav_since3["geometry"]["coordinates"][0][1].get<double>(), 43.0002, 1e-9);

  const json status = GetJson("/api/status");
  EXPECT_EQ(status["trajectory_corrected"], true);
  EXPECT_EQ(status["corrected_frames"], 2);
  const json frame = GetJson("/api/frames/1");
  EXPECT_DOUBLE_EQ(frame["lat"].get<double>(), 43.0001);  // placed
  ASSERT_TRUE(frame["nav"].is_object());
  EXPECT_DOUBLE_EQ(frame["nav"]["lat"].get<double>(), 43.0002);
  EXPECT_DOUBLE_EQ(frame["nav"]["heading_deg"].get<double>(), 97);
  for (const char* key : {"lat", "lon", "altitude_m", "depth_m", "heading_deg", "pitch_deg", "roll_deg"})
    EXPECT_TRUE(frame["nav"][key].is_number()) << key;
  EXPECT_TRUE(GetJson("/api/frames/3")["nav"].is_null()) << "frame 3 was not corrected";
  EXPECT_TRUE(GetJson("/api/frames?lat=43.00002&lon=5.00002")["frames"][0]["nav"].is_object());
}

TEST_F(HttpServerTest, CorrectedFramesAddedLiveJoinTheNavTrack) {
  Start();
  FrameRecord f = test::MakeFrame(4, {43.0003, 5.0003}, 0.0002, "used", "");
  f.nav = NavigatedPose{{43.0004, 5.0004}};
  TrackPoint p;
  p.seq = 5;
  p.position = {43.0003, 5.0003};
  p.nav = NavigatedPosition{{43.0004, 5.0004}, 0};
  state_.AddFrame(f, p);
  EXPECT_EQ(GetJson("/api/status")["trajectory_corrected"], true);
  const json nav = GetJson("/api/track?source=nav&since=5");
  EXPECT_EQ(nav["properties"]["corrected"], true);
  ASSERT_EQ(nav["geometry"]["coordinates"].size(), 2u);
  EXPECT_NEAR(nav["geometry"]["coordinates"][0][1].get<double>(), 43.0002, 1e-9) << "point 4: not corrected";
  EXPECT_NEAR(nav["geometry"]["coordinates"][1][1].get<double>(), 43.0004, 1e-9) << "point 5: the navigation's";
}

}  // namespace
}  // namespace seamap::server
