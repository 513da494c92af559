// replay --refine-nav paints frames again at corrected poses: the server's
// copy of the mission takes their new records and track points in place.
#include <gtest/gtest.h>

#include "server/mission_state.h"
#include "tests/server/test_mission.h"

namespace seamap::server {
namespace {

TrackPoint Point(int seq, double lat) {
  TrackPoint p;
  p.seq = seq;
  p.time_s = seq * 0.2;
  p.position = {lat, 5};
  return p;
}

TEST(MissionStateRefine, AFramePaintedAgainReplacesItsRecordAndTrackPoint) {
  MissionState state;
  for (int i = 0; i < 3; ++i) state.AddFrame(test::MakeFrame(i, {43, 5}, 0.0002, "used", ""), Point(i, 43 + i * 1e-5));
  EXPECT_FALSE(state.TrajectoryCorrected());

  FrameRecord corrected = test::MakeFrame(1, {43.00002, 5}, 0.0002, "used", "");
  corrected.nav = NavigatedPose{{43, 5}, 2.5, 31, 90, 0, 0};
  TrackPoint point = Point(1, 43.00002);
  point.nav = NavigatedPosition{{43.00001, 5}, 90};
  state.AddFrame(corrected, point);

  const std::vector<TrackPoint> track = state.TrackFrom(0);
  ASSERT_EQ(track.size(), 3u);  // replaced, not appended
  EXPECT_DOUBLE_EQ(track[1].position.lat, 43.00002);
  ASSERT_TRUE(track[1].nav);
  EXPECT_DOUBLE_EQ(track[1].nav->position.lat, 43.00001);
  EXPECT_EQ(state.TrackSize(), 3);
  EXPECT_TRUE(state.TrajectoryCorrected());

  // Painted again once more without a correction: no longer counted as corrected.
  state.AddFrame(test::MakeFrame(1, {43.00001, 5}, 0.0002, "used", ""), Point(1, 43.00001));
  EXPECT_FALSE(state.TrajectoryCorrected());
  EXPECT_FALSE(state.TrackFrom(1)[0].nav);
}

}  // namespace
}  // namespace seamap::server
