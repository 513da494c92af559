#pragma once
// Decisions made before the first frame: zooms, colour, ground sample distance.
#include <cstddef>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/geo/local_frame.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"

namespace seamap {

struct MosaicPlan {
  int base_zoom = 0;
  int min_zoom = 0;
  int channels = 1;     // 1 gray, 3 colour
  double gsd_m = 0;     // ground sample distance at the median altitude
  double latitude = 0;  // survey latitude used for the zoom choice
};

// The base zoom matches the ground sample distance at the median altitude
// (unless set); the minimum zoom is where the whole survey spans one tile.
MosaicPlan PlanMosaic(const MapSettings& map, const CameraModel& camera, const LocalFrame& frame,
                      const std::vector<FrameSpec>& frames, int channels);

// The memory (bytes) painting one frame takes when its box at the base zoom
// is width x height global pixels: its warped pixels and the accumulators of
// the tiles under the box (tile_accumulator.h). Doubles: a hostile pose can
// make a box of more pixels than int64 holds.
double FramePaintBytes(double width_px, double height_px, int tile_size, int channels);

// Estimates, before anything is written, what painting a frame of the survey
// (nadir, at the median altitude) takes at the plan's base zoom, and throws
// an InputError naming base_zoom, the memory it would need and the largest
// zoom that fits when that is over memory_cap_mb.
void CheckPlanFitsMemory(const MosaicPlan& plan, const CameraModel& camera, int tile_size, int memory_cap_mb,
                         const std::string& source);

// The most one frame may take to paint (FramePaintBytes of its box): the
// memory cap, or 8 times a frame at the median altitude turned 45 degrees,
// whichever is more. A frame over it (far above the survey: thousands of
// tiles at the base zoom) is refused; frames a little higher or turned are not.
double FramePaintLimitBytes(const MosaicPlan& plan, const CameraModel& camera, int tile_size, int memory_cap_mb);

}  // namespace seamap
