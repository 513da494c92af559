// The track's two sources (estimated, nav), the track event and the mission's
// "trajectory corrected" state, without HTTP.
#include "server/track_feature.h"

#include <gtest/gtest.h>

#include "server/api_error.h"
#include "server/mission_state.h"
#include "tests/server/test_mission.h"

namespace seamap::server {
namespace {

TrackPoint Point(int seq, LatLon at, std::optional<LatLon> nav = std::nullopt) {
  TrackPoint p;
  p.seq = seq;
  p.time_s = seq * 2.0;
  p.position = at;
  p.heading_deg = 90;
  if (nav) p.nav = NavigatedPosition{*nav, 95};
  return p;
}

TEST(TrackSource, ParsesTheParameterAndNamesItWhenWrong) {
  EXPECT_EQ(ParseTrackSource(std::nullopt), TrackSource::kEstimated);
  EXPECT_EQ(ParseTrackSource("estimated"), TrackSource::kEstimated);
  EXPECT_EQ(ParseTrackSource("nav"), TrackSource::kNav);
  EXPECT_EQ(ParseTrackSource("buoy"), TrackSource::kBuoy);
  EXPECT_STREQ(TrackSourceName(TrackSource::kBuoy), "buoy");
  for (const std::string bad : {"", "NAV", "raw", "navigation"}) {
    try {
      ParseTrackSource(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status(), 400);
      EXPECT_NE(std::string(e.what()).find("parameter 'source'"), std::string::npos) << e.what();
    }
  }
}

TEST(TrackFeature, NavSourceUsesTheNavigationWhereCorrectedAndThePlacedPositionElsewhere) {
  const std::vector<TrackPoint> points = {Point(3, {43.0, 5.0}, LatLon{43.1, 5.1}), Point(4, {43.2, 5.2})};
  const auto nav = TrackFeature(points, TrackSource::kNav, 5, true);
  EXPECT_EQ(nav["properties"]["source"], "nav");
  EXPECT_EQ(nav["properties"]["corrected"], true);
  EXPECT_EQ(nav["properties"]["from"], 3);
  EXPECT_EQ(nav["properties"]["next"], 5);
  EXPECT_EQ(nav["geometry"]["coordinates"], nlohmann::json::parse("[[5.1, 43.1], [5.2, 43.2]]"));
  const auto estimated = TrackFeature(points, TrackSource::kEstimated, 5, true);
  EXPECT_EQ(estimated["properties"]["source"], "estimated");
  EXPECT_EQ(estimated["geometry"]["coordinates"], nlohmann::json::parse("[[5.0, 43.0], [5.2, 43.2]]"));
  EXPECT_EQ(estimated["properties"]["times"], nlohmann::json::parse("[6.0, 8.0]"));

  const auto lone = TrackFeature({Point(0, {43.0, 5.0}, LatLon{43.1, 5.1})}, TrackSource::kNav, 1, true);
  EXPECT_TRUE(lone["geometry"].is_null());
  EXPECT_EQ(lone["properties"]["coordinates"], nlohmann::json::parse("[[5.1, 43.1]]"));
}

TEST(TrackPointJson, CarriesTheNavigationsPositionWhenCorrected) {
  const auto corrected = TrackPointJson(Point(2, {43.0, 5.0}, LatLon{43.1, 5.1}));
  EXPECT_EQ(corrected["seq"], 2);
  EXPECT_DOUBLE_EQ(corrected["lat"].get<double>(), 43.0);
  EXPECT_DOUBLE_EQ(corrected["nav"]["lat"].get<double>(), 43.1);
  EXPECT_DOUBLE_EQ(corrected["nav"]["lon"].get<double>(), 5.1);
  EXPECT_DOUBLE_EQ(corrected["nav"]["heading_deg"].get<double>(), 95);
  EXPECT_TRUE(TrackPointJson(Point(2, {43.0, 5.0}))["nav"].is_null());
}

TEST(FrameJson, CarriesTheNavigationsPoseWhenCorrected) {
  FrameRecord f = test::MakeFrame(1, {43, 5}, 0.001, "used", "");
  EXPECT_TRUE(FrameJson(f)["nav"].is_null());
  f.nav = NavigatedPose{{43.001, 5.002}, 2.5, 31, 92, 1.5, -0.5};
  const auto nav = FrameJson(f)["nav"];
  EXPECT_DOUBLE_EQ(nav["lat"].get<double>(), 43.001);
  EXPECT_DOUBLE_EQ(nav["lon"].get<double>(), 5.002);
  EXPECT_DOUBLE_EQ(nav["altitude_m"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(nav["depth_m"].get<double>(), 31);
  EXPECT_DOUBLE_EQ(nav["heading_deg"].get<double>(), 92);
  EXPECT_DOUBLE_EQ(nav["pitch_deg"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(nav["roll_deg"].get<double>(), -0.5);
}

TEST(MissionState, SaysWhenTheTrajectoryIsCorrected) {
  MissionState state;
  state.AddFrame(test::MakeFrame(0, {43, 5}, 0.001, "used", ""), Point(0, {43, 5}));
  EXPECT_FALSE(state.TrajectoryCorrected());
  EXPECT_EQ(state.StatusJson()["trajectory_corrected"], false);
  EXPECT_EQ(state.StatusJson()["corrected_frames"], 0);

  FrameRecord corrected = test::MakeFrame(1, {43, 5}, 0.001, "used", "");
  corrected.nav = NavigatedPose{{43.001, 5.001}};
  state.AddFrame(corrected, Point(1, {43, 5}, LatLon{43.001, 5.001}));
  EXPECT_TRUE(state.TrajectoryCorrected());
  EXPECT_EQ(state.StatusJson()["trajectory_corrected"], true);
  EXPECT_EQ(state.StatusJson()["corrected_frames"], 1);
  state.AddFrame(corrected, Point(1, {43, 5}));  // painted again: counted once
  EXPECT_EQ(state.StatusJson()["corrected_frames"], 1);
}

}  // namespace
}  // namespace seamap::server
