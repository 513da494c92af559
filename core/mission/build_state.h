#pragma once
// A map's build state as `seamap info` and `seamap serve` tell it: the state
// its builder recorded (MissionMetadata::state), with "building" split in two: a
// process still holds the map's lock (MapLock) and is building it, or none
// does and the build was interrupted (killed, crashed, the power went). An
// interrupted map says how to go on.
#include <functional>
#include <optional>
#include <string>

#include "core/tiles/tile_store.h"

namespace seamap {

struct MapBuildState {
  // "complete", "building", "interrupted", "stopped" (a replay stopped by
  // its operator), or "" (no state recorded: not built by seamap).
  std::string state;
  std::optional<int> writer_pid;  // building: the process writing it (0: unknown)
  bool checkpoint = false;        // interrupted: it has a checkpoint to resume from
  bool folder = false;
  int frames_done = 0, frames_total = 0;  // at the checkpoint
  std::string command;                    // the interrupted build's command line, when recorded

  // For "interrupted": what happened and the command that goes on from here.
  std::string Explanation() const;
};

// `path` is the map's path as given to the store (for its lock file).
MapBuildState ReadBuildState(const std::string& path, const TileStore& store);
// The same with the recorded state from `recorded_state` (asked again when
// needed; a server reads it through its tile source) and the checkpoint from `store`.
MapBuildState ReadBuildState(const std::string& path, const std::function<std::string()>& recorded_state,
                             const TileStore& store);

}  // namespace seamap
