#pragma once
// What `build` and `replay` read before the first frame: config, camera,
// navigation, frame list (what they run: core/controllers/mission_build.h).
#include <memory>
#include <string>
#include <vector>

#include "cli/args.h"
#include "core/camera/camera_model.h"
#include "core/controllers/mission_build.h"
#include "core/detect/yolo_model.h"
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

// The controller's options for these inputs (the map and what paints it
// are the caller's to add).
MissionBuildOptions MissionOptions(BuildInputs in);

// --detect: the recogniser of cli/detect_setup.h hooked up to the mission
// (`model` null: none).
void HookUpDetector(std::shared_ptr<const YoloModelInfo> model, MissionBuildOptions* options);

// --trajectory-out FILE: refused before the build when its folder does not
// exist; written from the finished mission (the poses the frames were placed
// with, core/controllers/mission_trajectory_io.h) with a line on stdout.
void CheckTrajectoryOut(const std::string& path);
void WriteTrajectoryOut(const TileStore& store, const std::string& path);

// --terrain (estimate the seabed) or --terrain-file DEM, and the estimate's
// knobs (--max-relief, --dem-cell, --dem-max-sigma, --terrain-points,
// --terrain-from-bundle: refused without --terrain). Args must know the
// flags "terrain" and "terrain-from-bundle".
void ReadTerrainOptions(Args& args, TerrainSettings* terrain);

}  // namespace seamap::cli
