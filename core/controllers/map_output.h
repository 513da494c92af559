#pragma once
// The map a build (or replay) writes: opened only when what the command line
// asks for fits what is there (a new map, --overwrite, --append, --resume),
// and held against other writers for the whole build (MapLock).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/mosaic/build_checkpointer.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct OutputChoice {
  bool append = false, overwrite = false, resume = false;
};

struct MapOutput {
  MapLock lock;  // released after the store is closed
  std::unique_ptr<TileStore> store;
  std::optional<BuildProgress> checkpoint;  // --resume: the main layer's
};

// Opens the output map. An existing map is refused unless --append or
// --overwrite; --resume needs an interrupted MBTiles map with a checkpoint;
// an interrupted map is appended to only through --resume. InputErrors
// name the option.
MapOutput OpenOutput(const std::string& path, const BuildConfig& config, const OutputChoice& choice);

// --append: drops the frames whose image is already in the map (recorded
// before `checkpoint` when resuming an append) and numbers the rest from 0.
// Returns the names dropped.
std::vector<std::string> SkipFramesInMap(const TileStore& store, const std::optional<BuildProgress>& checkpoint,
                                         std::vector<FrameSpec>* frames);

// --resume: the frames the checkpoint covers must be the survey's first
// ones, image for image; InputError naming --nav (or --images) otherwise.
void CheckSameSurvey(const TileStore& store, const BuildProgress& checkpoint, const std::vector<FrameSpec>& frames);

}  // namespace seamap
