#pragma once
// Decisions made before the first frame: zooms, colour, ground sample distance.
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

}  // namespace seamap
