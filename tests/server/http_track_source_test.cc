// GET /api/track?source=refined: served where the mission's trajectory was
// refined (seamap_trajectory mode "refine"), 404 naming why where it was not;
// the default and "estimated" stay the placed track whatever its kind.
#include "core/mission/mission_metadata.h"
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

// The test mission as if refined (mode) or filtered: the navigation had each point 0.0001 deg further north.
void CorrectTheTestMission(const std::filesystem::path& path, const std::string& mode) {
  MBTilesStore store(path.string());
  for (auto p : store.Track()) {
    p.nav = NavigatedPosition{{p.position.lat + 0.0001, p.position.lon}, 97};
    store.PutTrackPoint(p);
  }
  MissionMetadata m;
  m.trajectory = nlohmann::json{{"mode", mode}};
  WriteMissionMetadata(&store, m);
  store.Flush();
}

TEST_F(HttpServerTest, ARefinedMissionServesItsRefinedTrack) {
  CorrectTheTestMission(mission_.path, "refine");
  Start();
  const json refined = GetJson("/api/track?source=refined");
  const json best = GetJson("/api/track");
  const json nav = GetJson("/api/track?source=nav");
  EXPECT_EQ(refined["properties"]["source"], "refined");
  EXPECT_EQ(refined["properties"]["corrected"], true);
  EXPECT_EQ(refined["geometry"], best["geometry"]);  // the default: the best the mission has
  EXPECT_EQ(refined["geometry"], GetJson("/api/track?source=estimated")["geometry"]);  // the console's, unchanged
  ASSERT_EQ(refined["geometry"]["coordinates"].size(), 5u);
  EXPECT_NEAR(refined["geometry"]["coordinates"][2][1].get<double>(), 43.0001, 1e-9);
  EXPECT_NEAR(nav["geometry"]["coordinates"][2][1].get<double>(), 43.0002, 1e-9);
  // `since` as for the others.
  EXPECT_EQ(GetJson("/api/track?source=refined&since=3")["properties"]["from"], 2);
}

TEST_F(HttpServerTest, TheRefinedTrackOfAMissionWithoutOneIsNotFound) {
  Start();  // placed with the navigation as given
  ExpectError(Get("/api/track?source=refined"), 404, "not refined", "uncorrected mission");
  ExpectError(Get("/api/track?source=refined"), 404, "navigation as given", "uncorrected mission");
  EXPECT_EQ(GetJson("/api/track?source=nav")["properties"]["source"], "nav");
}

TEST_F(HttpServerTest, AFilteredMissionHasNoRefinedTrack) {
  CorrectTheTestMission(mission_.path, "ekf");
  Start();
  ExpectError(Get("/api/track?source=refined"), 404, "source 'estimated'", "filtered mission");
  EXPECT_EQ(GetJson("/api/track?source=estimated")["properties"]["corrected"], true);
  ExpectError(Get("/api/track?source=smoothed"), 400, "'refined'", "the error lists the sources");
}

}  // namespace
}  // namespace seamap::server
