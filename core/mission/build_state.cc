#include "core/mission/build_state.h"

#include <nlohmann/json.hpp>

#include "core/mission/mission_metadata.h"
#include "core/tiles/map_lock.h"

namespace seamap {
MapBuildState ReadBuildState(const std::string& path, const TileStore& store) {
  return ReadBuildState(
      path, [&store] { return ReadMissionMetadata(store).StateOrEmpty(); }, store);
}

MapBuildState ReadBuildState(const std::string& path, const std::function<std::string()>& recorded_state,
                             const TileStore& store) {
  MapBuildState s;
  s.folder = !IsMBTilesPath(path);
  s.state = recorded_state();
  if (s.state != "building") return s;
  s.writer_pid = MapLock::Holder(path);
  if (s.writer_pid) return s;
  // A builder records "complete" before it lets go of the lock: read again.
  s.state = recorded_state();
  if (s.state != "building") return s;
  s.state = "interrupted";
  if (auto checkpoint = ReadStoredCheckpoint(store)) {
    s.checkpoint = true;
    try {  // the builder's counters (core/mosaic/build_checkpointer.h)
      const nlohmann::json j = nlohmann::json::parse(checkpoint->progress);
      s.frames_done = j.value("frame_index", -1) + 1;
      s.frames_total = j.value("frames_total", 0);
      s.command = j.value("command", "");
    } catch (const nlohmann::json::exception&) {
    }
  }
  return s;
}

std::string MapBuildState::Explanation() const {
  if (state != "interrupted") return "";
  std::string what = "the build stopped without finishing and no process is writing the map";
  if (checkpoint)
    return what + "; " + std::to_string(frames_done) + " of " + std::to_string(frames_total) +
           " frames are safe. Resume with: " + (command.empty() ? "seamap build <same arguments>" : command) +
           " --resume";
  if (folder)
    return what +
           "; a tile folder keeps no checkpoints (an .mbtiles map does). Start again with: "
           "seamap build <same arguments> --overwrite";
  return what +
         " and it has no checkpoint (written by seamap replay or an older seamap). Add the missing "
         "frames with: seamap build <same arguments> --append, or start again with --overwrite";
}

}  // namespace seamap
