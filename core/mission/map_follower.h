#pragma once
// A map another process may be writing (`seamap build`, `seamap replay`,
// `seamap detect`...), followed from its file: what changed since the last
// look. `seamap serve MAP` and each open mission of a catalogue follow their
// maps with it, under the same rules; the server turns what it reports into
// reloads and live events. Knows nothing of HTTP.
#include <functional>
#include <string>

#include "core/mission/build_state.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct MapFollowStep {
  MapBuildState build;  // as read now
  // The state a reader shows: "building", "complete", "interrupted" or
  // "stopped" (a stopped replay, or no state recorded).
  std::string state;
  std::string state_detail;    // interrupted: what happened and how to go on
  bool state_changed = false;  // while followed (the first step: always)
  // The records (frames, track, progress) may have changed: reload them. True
  // while it is being built and once more when that ends.
  bool reload_records = false;
  // Another process holds it for writing: its tiles must not be cached for long.
  bool being_written = false;
};

class MapFollower {
 public:
  // `path`: the map as given to its store (for the lock file); `recorded_state`
  // reads its seamap_state again (a server asks its tile source).
  MapFollower(std::string path, std::function<std::string()> recorded_state);

  // Reads the map's state from `records` (its checkpoint) and the lock; call
  // every couple of seconds. The first step reports the state as found.
  MapFollowStep Step(const TileStore& records);

 private:
  std::string path_;
  std::function<std::string()> recorded_state_;
  bool first_ = true;
  std::string state_seen_;  // MapBuildState::state at the last step
};

}  // namespace seamap
