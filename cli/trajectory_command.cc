// seamap trajectory: a survey's trajectory estimated from its photos.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/trajectory_setup.h"
#include "core/camera/camera_model.h"
#include "core/controllers/pose_source.h"
#include "core/controllers/trajectory_georef.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/trajectory/trajectory_csv.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap trajectory --images DIR --nav FILE --camera FILE --mode vo|ekf|refine --out trajectory.csv\n"
    "                         [--origin LAT,LON] [--image-times FILE] [--report report.json] [options]\n"
    "\n"
    "  --mode vo           seed 003: visual odometry (altitude for scale) in a Kalman filter with the\n"
    "                      attitude as input and depth; the navigation's positions only for the first fix\n"
    "  --mode ekf          the same filter also fusing the navigation's positions, gated (USBL, GPS)\n"
    "  --mode refine       the whole survey at once: every overlapping pair of frames registered on the\n"
    "                      seabed (along the track and across lines and loops), one robust pose graph\n"
    "  --out FILE          trajectory.csv (image,time_s,lat,lon,x_m,y_m,depth_m,altitude_m,heading_deg,\n"
    "                      pitch_deg,roll_deg[,flags]), read as is by seamap build --nav\n"
    "  --report FILE       the run's figures as JSON (pairs, inliers, residuals, seconds per stage)\n"
    "  --points FILE       refine's triangulated seabed points as CSV (x_m,y_m,up_m,sigma_up_m,views: local\n"
    "                      metres, heights up with the sea surface 0)\n"
    "  --config FILE       a build config: its \"navigation\" object (columns, origin, noise)\n"
    "  --threads N         worker threads (default: one per core)\n"
    "  --quiet             no progress bars\n"
    "on the Earth without absolute fixes (--mode vo or refine): seed 002's towed buoy, as seamap georef\n"
    "  --buoy FILE         the buoy's GPS fixes: CSV time_s,lat,lon (or easting,northing,zone), same clock\n"
    "  --tether-length M   the tether's length, metres\n"
    "  --depth M | --depth-csv FILE   the vehicle's depth (default: the trajectory's own depth_m)\n"
    "  --buoy-method M     tether (default), umeyama or triangle (see seamap georef --help)\n"
    "  --georef-report F   the fit's report (scale, residuals, predicted_rmse_m; default OUT.georef.json)\n"
    "                      --out then holds the trajectory moved by the fit, in the survey's local frame\n";

// --buoy and its companions: the towed-buoy fit's options (BuoyGeorefOptions
// as seamap georef reads them), checked before the photos are read. Without
// --depth/--depth-csv the trajectory's own depths are the depth log.
std::optional<BuoyGeorefOptions> ReadBuoyOptions(Args& args, const std::string& mode, const std::string& out) {
  const std::optional<std::string> buoy = args.Get("buoy");
  if (!buoy) {
    for (const char* option : {"tether-length", "depth", "depth-csv", "buoy-method", "georef-report"})
      if (args.Get(option)) throw InputError("", 0, std::string("--") + option, "goes with --buoy FILE");
    return std::nullopt;
  }
  if (mode == "ekf")
    throw InputError("", 0, "--buoy",
                     "puts a trajectory without absolute fixes on the Earth: use --mode vo or refine (ekf already "
                     "fuses the navigation's positions)");
  BuoyGeorefOptions in;
  in.keyframes_source = "the " + mode + " trajectory";
  in.buoy_file = *buoy;
  in.tether_length_m = args.GetDouble("tether-length", NAN);
  if (std::isnan(in.tether_length_m))
    throw InputError("", 0, "--tether-length", "is required with --buoy: the tether length in metres");
  if (args.Get("depth")) in.depth_m = args.GetDouble("depth", 0);
  in.depth_file = args.GetOr("depth-csv", "");
  const std::string method = args.GetOr("buoy-method", "tether");
  if (method == "triangle")
    in.georef.method = GeorefMethod::kTriangle;
  else if (method == "umeyama")
    in.georef.method = GeorefMethod::kUmeyama;
  else if (method != "tether")
    throw InputError("", 0, "--buoy-method", "expected tether, umeyama or triangle, got '" + method + "'");
  in.georef.tether_length_m = in.tether_length_m;
  const std::filesystem::path out_path(out);
  in.report =
      args.GetOr("georef-report", (out_path.parent_path() / (out_path.stem().string() + ".georef.json")).string());
  in.quiet = true;
  return in;
}

}  // namespace

int RunTrajectory(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"quiet", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s%s", kHelp, kNavigationNoiseHelp, kFeatureEnhanceHelp);
    return 0;
  }
  BuildConfig config;
  if (auto path = args.Get("config")) config = LoadBuildConfig(*path);
  const std::string mode = args.Require("mode");
  if (mode != "refine" && mode != "vo" && mode != "ekf")
    throw InputError("", 0, "--mode", "expected vo, ekf or refine, got '" + mode + "'");
  if (auto v = args.Get("origin")) {
    const LatLonArg o = ParseLatLon(*v, "--origin");
    config.nav.origin = LatLon{o.lat, o.lon};
  }
  const std::string out = args.Require("out");
  const std::optional<std::string> report_path = args.Get("report");
  const std::optional<std::string> points_path = args.Get("points");
  const bool quiet = args.Flag("quiet");
  const int threads = args.GetInt("threads", config.threads);
  const CameraModel camera = LoadCamera(args.Require("camera"));
  const std::string images = args.Require("images");
  std::error_code ec;
  if (!std::filesystem::is_directory(images, ec)) throw InputError(images, 0, "--images", "is not a folder of photos");
  const NavTable nav = ReadNavigation(args.Require("nav"), config.nav);
  FrameList frames = MatchFrames(nav, images, args.Get("image-times"));
  const RefineOptions options = ReadRefineOptions(args, config.navigation, threads);
  const FeatureEnhanceOptions feature_enhance = ReadFeatureEnhance(args);
  std::optional<BuoyGeorefOptions> buoy = ReadBuoyOptions(args, mode, out);
  args.RejectUnknown();
  // Without --depth/--depth-csv, the trajectory's own depths: a stand-in for the check, replaced below.
  const bool own_depth = buoy && buoy->depth_file.empty() && !buoy->depth_m;
  if (own_depth) buoy->depth_samples = {{0, 0}};
  if (buoy) buoy->Check();
  for (const auto& w : nav.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& r : nav.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  for (const auto& r : frames.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  if (frames.frames.size() < 2)
    throw InputError(nav.source, 0, "", "fewer than two frames to estimate a trajectory from");

  PoseSourceOptions poses;
  poses.mode = mode == "refine" ? PoseMode::kRefine : PoseMode::kFilter;
  poses.refine = options;
  if (mode != "refine") poses.filter = EstimatorOptionsFrom(mode, options, "--mode");
  poses.feature_enhance = feature_enhance;
  poses.threads = threads;
  poses.max_image_pixels = config.frames.max_image_pixels;
  poses.quiet = quiet;
  std::vector<std::string> flags;
  PoseSource source(camera, poses);
  nlohmann::json report = source.PlaceSurvey(&frames.frames, &flags);
  if (points_path) {
    std::ofstream file(*points_path);
    if (!file) throw InputError(*points_path, 0, "--points", "cannot write the points file");
    file << "x_m,y_m,up_m,sigma_up_m,views\n";
    char line[160];
    for (const SeabedPoint& p : source.seabed_points()) {
      std::snprintf(line, sizeof(line), "%.4f,%.4f,%.4f,%.4f,%d\n", p.east_north_up_m.x(), p.east_north_up_m.y(),
                    p.east_north_up_m.z(), p.sigma_up_m, p.views);
      file << line;
    }
  }
  const LocalFrame frame(nav.origin);
  std::vector<TrajectoryRow> rows;
  for (size_t i = 0; i < frames.frames.size(); ++i) {
    const FrameSpec& f = frames.frames[i];
    rows.push_back({f.image, f.time_s, f.pose, flags[i]});
  }
  if (buoy) {
    if (own_depth) {
      buoy->depth_samples.clear();
      for (const TrajectoryRow& r : rows)
        if (r.time_s) buoy->depth_samples.emplace_back(*r.time_s, r.pose.depth_m);
    }
    const TrajectoryGeoref placed = GeoreferenceTrajectory(rows, frame, *buoy);
    rows = placed.rows;
    std::printf(
        "on the Earth with the buoy (%s): scale %.4f (the trajectory is metric: ~1 expected), turned %.2f deg, "
        "start moved %.2f m; %d of %d frames in the fit, residual %.3f m RMS, expected error %.3f m -> %s\n",
        buoy->buoy_file.c_str(), placed.scale, placed.rotation_deg, placed.shift_m, placed.good, placed.keyframes,
        placed.residual_rmse_m, placed.predicted_rmse_m, buoy->report.c_str());
  }
  WriteTrajectoryCsv(out, rows, frame);
  std::printf("trajectory (%s%s): %zu frames -> %s\n", mode.c_str(), buoy ? ", buoy-georeferenced" : "", rows.size(),
              out.c_str());
  if (report_path) {
    report["mode"] = mode;
    std::ofstream file(*report_path);
    if (!file) throw InputError(*report_path, 0, "--report", "cannot write the report file");
    file << report.dump(2) << "\n";
  }
  return 0;
}

}  // namespace seamap::cli
