#include "server/mission_follow.h"

#include "server/track_feature.h"

namespace seamap::server {

void FollowRecords(MissionState& mission, EventHub& events, const TileStore& records, const std::string& state,
                   const std::string& detail) {
  const int track_before = mission.TrackSize();
  mission.Load(records);
  Progress p = mission.progress();
  p.state = state;
  p.state_detail = detail;
  mission.SetProgress(p);
  for (const TrackPoint& t : mission.TrackFrom(track_before)) events.Publish("track", TrackPointJson(t).dump());
  const auto status = mission.StatusJson();
  if (!status["last_pose"].is_null()) events.Publish("pose", status["last_pose"].dump());
  events.Publish("progress", status.dump());
}

}  // namespace seamap::server
