#pragma once
// A map another process is still building, followed from its file: reload
// the records and tell the browsers (new track points, the vehicle's pose,
// progress). Used by `seamap serve MAP` and by the catalogue's live missions.
#include <string>

#include "core/tiles/tile_store.h"
#include "server/event_hub.h"
#include "server/mission_state.h"

namespace seamap::server {

// Reloads `mission` from `records`, sets its state ("building", "complete",
// "stopped" or "interrupted") and detail, and publishes "track" events for
// the new points, then "pose" and "progress".
void FollowRecords(MissionState& mission, EventHub& events, const TileStore& records, const std::string& state,
                   const std::string& detail);

}  // namespace seamap::server
