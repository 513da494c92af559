#pragma once
// What `build` and `replay` read before the first frame: config, camera,
// navigation, frame list (the output map: cli/build_output.h).
#include <memory>
#include <string>
#include <vector>

#include "cli/args.h"
#include "core/camera/camera_model.h"
#include "core/geo/local_frame.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/nav/frame_list.h"
#include "core/tiles/tile_store.h"

namespace seamap::cli {

struct BuildInputs {
  BuildConfig config;
  std::string config_source = "build config";  // the file it came from, for errors
  CameraModel camera;
  LocalFrame frame{LatLon{0, 0}};
  FrameList frames;
  int channels = 1;
  std::vector<std::string> warnings;
};

// Reads --config, --camera, --nav, --images, --origin, --image-times and the
// setting overrides (--tile-format, --tile-size, --base-zoom, ...).
BuildInputs ReadBuildInputs(Args& args);

// Refuses (InputError naming base_zoom and the memory needed) settings whose
// tile buffer cannot hold one frame of the survey, before anything is written.
void CheckMemoryFits(const BuildInputs& inputs);

// Hooks for the configured enhancement chain (seeded from the first frames).
BuildHooks MakeHooks(const BuildInputs& inputs);

}  // namespace seamap::cli
