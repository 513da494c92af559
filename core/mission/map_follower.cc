#include "core/mission/map_follower.h"

#include <utility>

namespace seamap {

MapFollower::MapFollower(std::string path, std::function<std::string()> recorded_state)
    : path_(std::move(path)), recorded_state_(std::move(recorded_state)) {}

MapFollowStep MapFollower::Step(const TileStore& records) {
  MapFollowStep step;
  step.build = ReadBuildState(path_, recorded_state_, records);
  const std::string& now = step.build.state;
  step.state = now == "building" || now == "complete" || now == "interrupted" ? now : "stopped";
  step.state_detail = step.build.Explanation();
  step.reload_records = !first_ && (now == "building" || state_seen_ == "building");
  // A map nobody builds does not change state (complete and stopped stay).
  step.state_changed = first_ || (step.reload_records && now != state_seen_);
  step.being_written = now == "building";
  first_ = false;
  state_seen_ = now;
  return step;
}

}  // namespace seamap
