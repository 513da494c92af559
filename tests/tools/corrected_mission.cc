// corrected_mission: a mission whose trajectory was corrected, for the tests
// (the console's browser test) until `seamap build --refine-nav` exists.
//
//   corrected_mission SURVEY OUT.mbtiles [--pace-ms MS]
//
// SURVEY is a `seamap simulate` folder. Every frame is placed at its true pose
// (nav_truth.csv) and keeps the navigation's (nav.csv, with the errors
// simulate put in) beside it: what a perfect refiner would give. --pace-ms
// waits between frames, so `seamap serve` can follow a mission that grows.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/camera/camera_model.h"
#include "core/mission/mission_metadata.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"

namespace {

int Run(int argc, char** argv) {
  using namespace seamap;
  if (argc != 3 && !(argc == 5 && std::string(argv[3]) == "--pace-ms")) {
    std::fprintf(stderr, "usage: corrected_mission SURVEY OUT.mbtiles [--pace-ms MS]\n");
    return 2;
  }
  const std::string survey = argv[1], out = argv[2];
  const int pace_ms = argc == 5 ? std::atoi(argv[4]) : 0;

  const CameraModel camera = LoadCamera(survey + "/camera.json");
  NavReadOptions options;  // simulate writes local x_m, y_m; its origin is in survey.json
  const nlohmann::json description = nlohmann::json::parse(std::ifstream(survey + "/survey.json"));
  options.origin = LatLon{description.at("origin").at(0).get<double>(), description.at("origin").at(1).get<double>()};
  const NavTable nav = ReadNavigation(survey + "/nav.csv", options);
  const NavTable truth = ReadNavigation(survey + "/nav_truth.csv", options);
  FrameList frames = MatchFrames(nav, survey + "/photo", std::nullopt);
  const FrameList true_frames = MatchFrames(truth, survey + "/photo", std::nullopt);
  std::map<std::string, VehiclePose> true_pose;
  for (const FrameSpec& f : true_frames.frames) true_pose[f.image] = f.pose;
  for (FrameSpec& f : frames.frames) {
    auto it = true_pose.find(f.image);
    if (it == true_pose.end()) throw std::runtime_error(f.image + ": not in nav_truth.csv");
    f.nav_pose = f.pose;
    f.pose = it->second;
  }

  const LocalFrame frame(nav.origin);
  BuildConfig config;
  config.map.name = "Corrected survey";
  // Held as seamap build holds it: a follower takes an unlocked "building" map for an interrupted one.
  const MapLock lock = MapLock::Acquire(out, "--out");
  auto store = OpenTileStore(out, "png", /*create=*/true);
  const MosaicPlan plan = PlanMosaic(config.map, camera, frame, frames.frames, 1);
  if (pace_ms > 0) {  // as a replay: commit often, tiles under the vehicle too, so a follower sees it grow
    config.buffer.batch_frames = 2;
    config.buffer.batch_seconds = 0;
    config.buffer.live_tiles = true;
  }
  MosaicBuilder builder(config, camera, frame, plan, store.get());
  seamap::MissionMetadata layers;
  layers.layers = std::vector<std::string>{"raw"};
  seamap::WriteMissionMetadata(store.get(), layers);
  if (pace_ms == 0) builder.Foresee(frames.frames);
  for (const FrameSpec& f : frames.frames) {
    builder.Push(f);
    if (pace_ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(pace_ms));
  }
  builder.Finish();
  std::printf("corrected_mission: %d frames used -> %s\n", builder.stats().frames_used, out.c_str());
  return builder.stats().frames_used > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corrected_mission: %s\n", e.what());
    return 1;
  }
}
