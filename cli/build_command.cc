// seamap build: photos + navigation + camera -> tile pyramid.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "cli/args.h"
#include "cli/build_setup.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "cli/trajectory_setup.h"
#include "core/controllers/build_report.h"
#include "core/controllers/mission_build.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap build --images DIR --nav FILE --camera FILE --out PATH [options]\n"
    "\n"
    "  --images DIR        folder with the photos named in the navigation\n"
    "  --nav FILE          navigation CSV (or the seed paper's text format)\n"
    "  --camera FILE       camera model: JSON, or OpenCV calibration YAML/XML\n"
    "  --out PATH          NAME.mbtiles (one-file mission) or a folder for {z}/{x}/{y} tiles\n"
    "  --origin LAT,LON    origin of local x_m/y_m positions (WGS84 degrees)\n"
    "  --image-times FILE  CSV image,time_s when the navigation is a time series\n"
    "  --config FILE       build settings (JSON, see config/)\n"
    "  --enhance OPS       enhancement chain, e.g. default or flatfield,dehaze,clahe (see enhance)\n"
    "  --tile-format F     png | jpg | webp        --tile-size 256|512\n"
    "  --base-zoom Z       --min-zoom Z            --threads N\n"
    "  --name TEXT         map name in the metadata\n"
    "  --append            continue painting an existing map (tiles are read back and blended);\n"
    "                      frames whose image is already in it are skipped\n"
    "  --resume            continue an interrupted build (same arguments) from its last checkpoint\n"
    "  --overwrite         replace an existing map\n"
    "  --quiet             no progress bar\n"
    "  --report FILE       write the run's figures as JSON (frames, seconds, tiles, bytes, peak RSS)\n"
    "  --trajectory-out F  write the trajectory the frames were placed with (refined with --refine-nav) to F,\n"
    "                      in seamap trajectory's CSV form\n"
    "  --refine-nav        refine the navigation from the photos first (seamap trajectory --mode refine),\n"
    "                      then paint with the refined poses; the mission keeps the navigation's beside them\n"
    "  --terrain           a true orthophoto: estimate the seabed's shape from the photos (after --refine-nav\n"
    "                      when given) and project every pixel onto it instead of the plane at the altitude\n"
    "  --terrain-file DEM  the same onto a height model from elsewhere (GeoTIFF or any GDAL raster, metres up,\n"
    "                      in any CRS GDAL knows)\n"
    "  --max-relief M      with --terrain: how far the seabed may lie from the plane at the altitude (1.5)\n"
    "  --dem-cell M        with --terrain: the height model's cell (default: from the points' density)\n"
    "  --dem-max-sigma M   with --terrain: a cell less certain than this is a hole (0.05)\n"
    "  --terrain-points CSV with --terrain: seabed points from a stereo rig (seamap stereo-points) fitted\n"
    "                      with the photos' own\n"
    "  --terrain-from-bundle with --refine-nav --terrain: fit the height model to the seabed points the\n"
    "                      bundle adjustment estimated instead of matching the photos again\n"
    "  --feature-enhance off|auto|LIST  with --refine-nav: enhance the frames before their features are\n"
    "                      detected (seamap trajectory --help)\n"
    "  --detect            search tiles for objects as they are finished (seamap detect's recogniser)\n"
    "  --detect-model FILE its ONNX model (default: data/models/seabed_objects.onnx)\n";

void WriteReport(const std::string& path, const nlohmann::json& report) {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "--report", "cannot write the report file");
  out << report.dump(2) << "\n";
}

// A word as a POSIX shell reads it back.
std::string ShellWord(const std::string& w) {
  const bool plain = !w.empty() && w.find_first_not_of(
                                       "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                       "0123456789_@%+=:,./-") == std::string::npos;
  if (plain) return w;
  std::string out = "'";
  for (char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The command that started this build, to be repeated with --resume if it
// is interrupted: its directory, and its arguments less --resume / --overwrite.
std::string CommandLine(int argc, char** argv, int first) {
  std::error_code ec;
  const std::string dir = std::filesystem::current_path(ec).string();
  std::string out = ec ? std::string() : "cd " + ShellWord(dir) + " && ";
  out += "seamap build";
  for (int i = first; i < argc; ++i)
    if (std::string(argv[i]) != "--resume" && std::string(argv[i]) != "--overwrite") out += " " + ShellWord(argv[i]);
  return out;
}

}  // namespace

int RunBuild(int argc, char** argv, int first) {
  Args args(
      argc, argv, first,
      {"append", "overwrite", "resume", "quiet", "refine-nav", "terrain", "terrain-from-bundle", "detect", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s", kHelp, kNavigationNoiseHelp);
    return 0;
  }
  BuildInputs in = ReadBuildInputs(args);
  const std::vector<std::string> warnings = in.warnings;
  MissionBuildOptions options = MissionOptions(std::move(in));
  options.out = args.Require("out");
  options.append = args.Flag("append"), options.overwrite = args.Flag("overwrite"),
  options.resume = args.Flag("resume");
  const bool quiet = args.Flag("quiet");
  const bool refine = args.Flag("refine-nav") || options.config.navigation.refine;
  options.poses.refine = ReadRefineOptions(args, options.config.navigation, options.config.threads);
  if (refine) options.poses.mode = PoseMode::kRefine;
  ReadTerrainOptions(args, &options.config.terrain);
  options.poses.feature_enhance = ReadFeatureEnhance(args);
  options.poses.quiet = quiet;
  options.poses.max_image_pixels = options.config.frames.max_image_pixels;  // guards refine's reads too
  options.command = CommandLine(argc, argv, first);
  const std::optional<std::string> report = args.Get("report");
  const std::optional<std::string> trajectory_out = args.Get("trajectory-out");
  if (trajectory_out) CheckTrajectoryOut(*trajectory_out);
  HookUpDetector(LiveDetectArgs(args), &options);  // the model is checked before the map is opened
  args.RejectUnknown();

  const long rejected = static_cast<long>(options.survey.rejected.size());
  std::unique_ptr<ProgressBar> progress;
  MissionObserver observer;
  observer.on_note = [](const std::string& note) { std::fprintf(stderr, "seamap build: %s\n", note.c_str()); };
  observer.on_progress = [&](const BuildStats& s) { progress->Update(s.frames_seen - rejected); };
  std::unique_ptr<MissionBuild> built;
  observer.on_layers_finished = [&] {  // before the recogniser drains
    progress->Update(static_cast<long>(built->options().survey.frames.size()));
    progress->Finish();
    const BuildStats& s = built->stats();
    for (const auto& r : s.rejections) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
    const size_t skipped = built->skipped().size();
    std::printf("%s%s\n", BuildSummary(s).c_str(),
                skipped == 0 ? "" : ("; " + std::to_string(skipped) + " already in the map, skipped").c_str());
    if (const BuildStats* e = built->enhanced_stats()) std::printf("enhanced layer: %s\n", BuildSummary(*e).c_str());
  };
  built = std::make_unique<MissionBuild>(std::move(options), observer);
  MissionBuild& mission = *built;
  const MissionBuildOptions& o = mission.options();
  if (!mission.Open()) {
    std::printf("nothing to add: every frame is in the map already\n");
    return 0;
  }
  const MosaicPlan& plan = mission.plan();
  std::fprintf(stderr, "seamap build: %zu frames, GSD %.1f mm at %.3f N -> zooms %d..%d, %s tiles of %d px -> %s\n",
               o.survey.frames.size(), plan.gsd_m * 1000, plan.latitude, plan.min_zoom, plan.base_zoom,
               TileExtension(o.config.map.encoding.format).c_str(), o.config.map.tile_size, o.out.c_str());
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  mission.Start();
  progress = std::make_unique<ProgressBar>("frames", static_cast<long>(o.survey.frames.size()), !quiet);
  mission.Run();
  if (report) {
    nlohmann::json figures = BuildReportJson(mission.stats(), plan, mission.pose_report(), mission.skipped().size());
    if (const SeabedSurface& surface = mission.surface(); surface.grid)
      figures["terrain"] = {{"source", surface.source},
                            {"cells", {surface.grid->cols(), surface.grid->rows()}},
                            {"cell_m", surface.grid->cell_m},
                            {"hole_share", surface.hole_share},
                            {"painted_hole_share", surface.painted_hole_share},
                            {"painted_cell_m", surface.grid->cell_m / surface.painted_refine}};
    WriteReport(*report, figures);
  }
  if (trajectory_out) WriteTrajectoryOut(*mission.store(), *trajectory_out);
  if (mission.stats().frames_used == 0) {
    std::fprintf(stderr, "seamap build: error: no frame could be used\n");
    return 1;
  }
  return 0;
}

}  // namespace seamap::cli
