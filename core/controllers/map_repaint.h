#pragma once
// Painting a map's tiles again once the frames' poses have changed (live
// refinement): each tile is blended from scratch from every frame over it at
// its new pose, through a MosaicBuilder on a RepaintStore (repaint_store.h),
// so a tile painted again is what a build with those poses makes of it, not
// a blend of old pixels and new.
#include <vector>

#include "core/camera/camera_model.h"
#include "core/controllers/repaint_store.h"
#include "core/geo/local_frame.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/mosaic/mosaic_plan.h"
#include "core/nav/frame_list.h"

namespace seamap {

struct RepaintSetup {
  BuildConfig config;  // the build's, as an offline build has it (no live tiles)
  CameraModel camera;
  LocalFrame frame{LatLon{0, 0}};
  MosaicPlan plan;
  BuildHooks hooks;  // preprocess and surface; on_frame for a whole map's records
};

struct RepaintResult {
  int frames_painted = 0;
  size_t base_tiles = 0;  // written again
  size_t cleared = 0;     // tiles no frame paints any more, written empty (a whole map)
  TileSet written;  // every tile written, overviews and cleared ones included (the recogniser searches them again)
};

// The base tiles under a frame's footprint at its pose (none when the camera
// does not see the seabed).
TileSet FrameTiles(const CameraModel& camera, const LocalFrame& frame, const VehiclePose& pose, int zoom,
                   int tile_size);

// Paints every frame again at its pose onto a map painted before: every tile
// from scratch, overviews included; the frames' records and track points
// replaced (ids from 0: the map must hold these frames only), the state
// written as a build writes it. Tiles of the map that no frame paints now
// are written empty. `frames` in acquisition order.
RepaintResult RepaintWholeMap(TileStore* store, const RepaintSetup& setup, const std::vector<FrameSpec>& frames);

// Paints the base tiles `tiles` again from the frames over them (and their
// neighbours along the track, the handover partners) at their poses, then
// the overviews above them from their children. Records and metadata stay.
// `frames`: every frame so far, in acquisition order.
RepaintResult RepaintTiles(TileStore* store, const RepaintSetup& setup, const std::vector<FrameSpec>& frames,
                           const TileSet& tiles);

}  // namespace seamap
