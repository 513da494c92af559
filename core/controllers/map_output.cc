#include "core/controllers/map_output.h"

#include <filesystem>
#include <set>

#include "core/mission/mission_metadata.h"
#include "core/util/error.h"

namespace seamap {
namespace fs = std::filesystem;

MapOutput OpenOutput(const std::string& path, const BuildConfig& config, const OutputChoice& choice) {
  if (choice.append && choice.overwrite) throw InputError("", 0, "--append", "cannot be combined with --overwrite");
  if (choice.resume && choice.overwrite) throw InputError("", 0, "--resume", "cannot be combined with --overwrite");
  MapOutput out;
  out.lock = MapLock::Acquire(path, "--out");  // from here on no other process writes it
  std::error_code ec;
  const bool mbtiles = IsMBTilesPath(path);
  const bool exists = mbtiles ? fs::exists(path, ec) : (fs::exists(path, ec) && !fs::is_empty(path, ec));
  if (choice.resume) {
    if (!exists) throw InputError(path, 0, "--resume", "no such map to resume");
    if (!mbtiles)
      throw InputError(path, 0, "--resume",
                       "a tile folder keeps no checkpoints and cannot be resumed (an .mbtiles map can); start "
                       "again with --overwrite");
  }
  // Holding the lock, a map still "building" is one whose build was interrupted.
  std::unique_ptr<TileStore> existing = exists ? OpenExistingMap(path, /*writable=*/false) : nullptr;
  const std::string state = existing ? ReadMissionMetadata(*existing).StateOrEmpty() : "";
  const bool checkpoint = existing && ReadStoredCheckpoint(*existing).has_value();
  existing.reset();
  const bool interrupted = state == "building";
  if (choice.resume) {
    if (state == "complete")
      throw InputError(path, 0, "--resume", "is complete: there is nothing to resume (--append adds frames to it)");
    if (!interrupted)
      throw InputError(path, 0, "--resume",
                       "was not interrupted (its state is \"" + state + "\"): there is nothing to resume");
    if (!checkpoint)
      throw InputError(path, 0, "--resume",
                       "has no checkpoint (written by seamap replay or an older seamap): continue it with --append, "
                       "or start again with --overwrite");
  } else if (exists && interrupted && checkpoint && !choice.overwrite) {
    throw InputError(path, 0, choice.append ? "--append" : "--out",
                     "was interrupted while it was being built: finish it first with seamap build <the arguments it "
                     "was built with> --resume, or start again with --overwrite");
  } else if (exists && !choice.append) {
    if (!choice.overwrite)
      throw InputError(path, 0, "--out",
                       "already exists; use --append to continue painting it or --overwrite to replace it");
    RemoveMap(path, "--out");
  }
  out.store = OpenTileStore(path, TileExtension(config.map.encoding.format), /*create=*/true);
  if (choice.resume) {
    try {
      out.checkpoint = BuildProgress::FromJson(ReadStoredCheckpoint(*out.store)->progress);
    } catch (const std::runtime_error& e) {
      throw InputError(path, 0, "--resume", e.what());
    }
  }
  return out;
}

std::vector<std::string> SkipFramesInMap(const TileStore& store, const std::optional<BuildProgress>& checkpoint,
                                         std::vector<FrameSpec>* frames) {
  // Resuming an append, the frames it had recorded are its own, not the map's before it.
  const int before = checkpoint ? checkpoint->frame_id_offset : INT32_MAX;
  std::set<std::string> in_map;
  for (const FrameRecord& f : store.Records().Frames())
    if (f.id < before) in_map.insert(f.image);
  std::vector<std::string> skipped;
  std::vector<FrameSpec> kept;
  for (FrameSpec& f : *frames) {
    if (in_map.count(f.image)) {
      skipped.push_back(f.image);
      continue;
    }
    f.index = static_cast<int>(kept.size());
    kept.push_back(std::move(f));
  }
  frames->swap(kept);
  return skipped;
}

void CheckSameSurvey(const TileStore& store, const BuildProgress& checkpoint, const std::vector<FrameSpec>& frames) {
  const int first = checkpoint.frame_id_offset, last = first + checkpoint.frame_index;
  if (checkpoint.frame_index >= static_cast<int>(frames.size()))
    throw InputError("", 0, "--nav",
                     "names " + std::to_string(frames.size()) + " frames; the interrupted build had done " +
                         std::to_string(checkpoint.frame_index + 1) + " of " + std::to_string(checkpoint.frames_total) +
                         ": resume with the same survey");
  for (const FrameRecord& f : store.Records().Frames()) {
    if (f.id < first || f.id > last) continue;
    const FrameSpec& spec = frames[f.id - first];
    if (spec.image != f.image)
      throw InputError("", 0, "--nav",
                       "frame " + std::to_string(f.id - first) + " is " + spec.image +
                           ", but the interrupted build painted " + f.image +
                           " there: resume with the same survey (--nav, --images) as the build that was interrupted");
  }
}

}  // namespace seamap
