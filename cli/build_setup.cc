#include "cli/build_setup.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "cli/detect_setup.h"
#include "core/controllers/mission_trajectory_io.h"
#include "core/enhance/enhance_chain.h"
#include "core/mission/mission_trajectory.h"
#include "core/mosaic/survey_channels.h"
#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "server/server_options.h"

namespace seamap::cli {
namespace fs = std::filesystem;

BuildInputs ReadBuildInputs(Args& args) {
  BuildInputs in;
  if (auto path = args.Get("config")) {
    in.config = LoadBuildConfig(*path);
    in.config_source = *path;
    // The "server" object is the server's to read; a mistake in it is
    // reported whichever command reads the file.
    if (in.config.server) server::ServerOptions::FromJson(*in.config.server, *path);
  }
  if (auto ops = args.Get("enhance")) {
    in.config.enhance = EnhanceChain::FromOpList(*ops, "--enhance").ToJson();
    if (in.config.layers == "raw") in.config.layers = "enhanced";
  }
  nlohmann::json overrides = nlohmann::json::object();
  if (auto v = args.Get("tile-format")) overrides["tile_format"] = *v;
  if (auto v = args.Get("name")) overrides["name"] = *v;
  for (const char* key : {"tile-size", "base-zoom", "min-zoom", "threads"}) {
    std::string k = key;
    if (args.Get(k)) {
      std::string json_key = k;
      for (char& c : json_key)
        if (c == '-') c = '_';
      overrides[json_key] = args.GetInt(k, 0);
    }
  }
  ApplyBuildConfig(overrides, "command line", &in.config);
  if (auto v = args.Get("origin")) {
    LatLonArg o = ParseLatLon(*v, "--origin");
    in.config.nav.origin = LatLon{o.lat, o.lon};
  }
  if (auto v = args.Get("utm-zone")) in.config.nav.utm_zone = args.GetInt("utm-zone", 0);

  in.camera = LoadCamera(args.Require("camera"));
  const std::string images = args.Require("images");
  std::error_code ec;
  if (!fs::is_directory(images, ec)) throw InputError(images, 0, "--images", "is not a folder of photos");
  NavTable nav = ReadNavigation(args.Require("nav"), in.config.nav);
  in.frame = LocalFrame(nav.origin);
  std::optional<std::string> image_times = args.Get("image-times");
  in.frames = MatchFrames(nav, images, image_times);
  in.warnings = nav.warnings;
  in.warnings.insert(in.warnings.end(), in.frames.warnings.begin(), in.frames.warnings.end());
  in.frames.rejected.insert(in.frames.rejected.begin(), nav.rejected.begin(), nav.rejected.end());
  const SurveyChannels channels = DecideChannels(in.frames.frames, in.config.frames.max_image_pixels);
  in.channels = channels.channels;
  if (!channels.warning.empty()) in.warnings.push_back(channels.warning);
  return in;
}

MissionBuildOptions MissionOptions(BuildInputs in) {
  MissionBuildOptions o;
  o.config = std::move(in.config);
  o.config_source = std::move(in.config_source);
  o.camera = std::move(in.camera);
  o.frame = in.frame;
  o.survey = std::move(in.frames);
  o.channels = in.channels;
  return o;
}

void HookUpDetector(std::shared_ptr<const YoloModelInfo> model, MissionBuildOptions* options) {
  if (!model) return;
  const MissionBuildOptions& o = *options;
  options->start_detector = [model, tile_size = o.config.map.tile_size, origin = o.frame.origin(),
                             detect = o.config.detect,
                             source = o.config_source](const MosaicPlan& plan, const TileStore* store) {
    return StartLiveDetector(model, plan, tile_size, origin, store, detect, source);
  };
  options->finish_detector = [](LiveDetector& detector, TileStore& store, const LiveDetector::Found& publish) {
    FinishLiveDetector(detector, store, publish);
  };
}

void CheckTrajectoryOut(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (path.empty() || fs::is_directory(path, ec) || (!parent.empty() && !fs::is_directory(parent, ec)))
    throw InputError(path, 0, "--trajectory-out", "expected a file in an existing folder (trajectory.csv)");
}

void WriteTrajectoryOut(const TileStore& store, const std::string& path) {
  const size_t rows = WriteMissionTrajectory(store, path, "--trajectory-out");
  std::printf("trajectory (%s): %zu frames -> %s\n", TrajectorySourceName(MissionTrajectory::Read(store).placed()),
              rows, path.c_str());
}

void ReadTerrainOptions(Args& args, TerrainSettings* terrain) {
  const bool estimate_terrain = args.Flag("terrain");
  if (auto file = args.Get("terrain-file")) {
    if (estimate_terrain)
      throw InputError("", 0, "--terrain-file", "and --terrain: give one (a height model's file, or estimate it)");
    *terrain = TerrainSettings{false, *file};
  } else if (estimate_terrain) {
    *terrain = TerrainSettings{true, ""};
  }
  // The estimate's knobs: only where there is an estimate to tune.
  for (const auto& [name, value] : {std::pair<const char*, double*>{"max-relief", &terrain->max_relief_m},
                                    {"dem-cell", &terrain->cell_m},
                                    {"dem-max-sigma", &terrain->max_sigma_m}}) {
    if (!args.Get(name)) continue;
    if (!terrain->estimate)
      throw InputError("", 0, std::string("--") + name,
                       "applies to the height model --terrain estimates; add --terrain");
    *value = args.GetDouble(name, 0);
    if (!(*value > 0 && *value <= 1000))
      throw InputError("", 0, std::string("--") + name, "expected metres in (0, 1000]");
  }
  if (auto points = args.Get("terrain-points")) {
    if (!terrain->estimate)
      throw InputError("", 0, "--terrain-points", "applies to the height model --terrain estimates; add --terrain");
    terrain->points_file = *points;
  }
  if (args.Flag("terrain-from-bundle")) {
    if (!terrain->estimate)
      throw InputError("", 0, "--terrain-from-bundle",
                       "applies to the height model --terrain estimates; add --terrain");
    terrain->from_bundle = true;
  }
}

}  // namespace seamap::cli
