// seamap trajectory: a survey's trajectory estimated from its photos.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <future>

#include <filesystem>
#include <fstream>
#include <set>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/trajectory_setup.h"
#include "core/camera/camera_model.h"
#include "core/image/image_read.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/trajectory/trajectory_csv.h"
#include "core/trajectory/trajectory_estimator.h"
#include "core/util/error.h"
#include "core/util/progress.h"
#include "core/util/thread_pool.h"

namespace seamap::cli {
namespace {

// Features on the pool, a bounded stretch ahead; the filter in order.
nlohmann::json EstimateFrames(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                              const EstimatorOptions& options, int threads, bool quiet,
                              std::vector<TrajectoryRow>* rows) {
  for (const FrameSpec& f : frames)
    if (!f.time_s) throw InputError(f.image_path, f.nav_line, "time_s", "vo and ekf need the navigation's times");
  ThreadPool pool(threads);
  TrajectoryEstimator estimator(camera, options);
  ProgressBar progress("frames", static_cast<long>(frames.size()), !quiet);
  std::deque<std::future<std::optional<FrameFeatures>>> ahead;
  size_t next = 0;
  const size_t depth = 4 * static_cast<size_t>(pool.size());
  const auto start = std::chrono::steady_clock::now();
  int unreadable = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    for (; next < frames.size() && next < i + depth; ++next)
      ahead.push_back(pool.Submit([&, next]() -> std::optional<FrameFeatures> {
        std::string problem;
        const cv::Mat image = ReadGuardedImage(frames[next].image_path, &problem);
        if (image.empty()) return std::nullopt;
        return DetectFeatures(image, camera, options.vo.features);
      }));
    const std::optional<FrameFeatures> features = ahead.front().get();
    ahead.pop_front();
    unreadable += !features;
    const VehiclePose pose = estimator.Add(features ? &*features : nullptr, *frames[i].time_s, frames[i].pose);
    rows->push_back({frames[i].image, frames[i].time_s, pose, features ? "" : "no_image"});
    progress.Update(static_cast<long>(i + 1));
  }
  progress.Finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& vo = estimator.vo_counts();
  const auto& filter = estimator.filter_counts();
  std::fprintf(stderr,
               "%s: %d VO measurements (%d homography, %d essential, %d hover), %d pairs failed, %d low-texture "
               "frames; filter took %d, gated %d VO updates (mean NIS %.2f), %d re-acquisitions; %.1f frames/s\n",
               options.mode == EstimatorMode::kVo ? "vo" : "ekf", vo.measurements, vo.homography, vo.essential,
               vo.hover, vo.failed_pairs, vo.low_texture, filter.velocity_accepted, filter.velocity_rejected,
               filter.velocity_accepted ? filter.velocity_nis_sum / filter.velocity_accepted : 0.0,
               filter.reacquisitions, frames.size() / std::max(seconds, 1e-9));
  return {{"frames", frames.size()},
          {"unreadable_frames", unreadable},
          {"vo_measurements", vo.measurements},
          {"homography", vo.homography},
          {"essential", vo.essential},
          {"hover", vo.hover},
          {"failed_pairs", vo.failed_pairs},
          {"low_texture_frames", vo.low_texture},
          {"missing_altitude", vo.missing_altitude},
          {"velocity_accepted", filter.velocity_accepted},
          {"velocity_rejected", filter.velocity_rejected},
          {"mean_vo_nis", filter.velocity_accepted ? filter.velocity_nis_sum / filter.velocity_accepted : 0.0},
          {"depth_rejected", filter.depth_rejected},
          {"position_accepted", filter.position_accepted},
          {"position_rejected", filter.position_rejected},
          {"reacquisitions", filter.reacquisitions},
          {"seconds", seconds},
          {"frames_per_s", frames.size() / std::max(seconds, 1e-9)}};
}

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
    "  --config FILE       a build config: its \"navigation\" object (columns, origin, noise)\n"
    "  --threads N         worker threads (default: one per core)\n"
    "  --quiet             no progress bars\n";

}  // namespace

int RunTrajectory(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"quiet", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s", kHelp, kNavigationNoiseHelp);
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
  const bool quiet = args.Flag("quiet");
  const int threads = args.GetInt("threads", config.threads);
  const CameraModel camera = LoadCamera(args.Require("camera"));
  const std::string images = args.Require("images");
  std::error_code ec;
  if (!std::filesystem::is_directory(images, ec)) throw InputError(images, 0, "--images", "is not a folder of photos");
  const NavTable nav = ReadNavigation(args.Require("nav"), config.nav);
  FrameList frames = MatchFrames(nav, images, args.Get("image-times"));
  const RefineOptions options = ReadRefineOptions(args, config.navigation, threads);
  args.RejectUnknown();
  for (const auto& w : nav.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& r : nav.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  for (const auto& r : frames.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  if (frames.frames.size() < 2)
    throw InputError(nav.source, 0, "", "fewer than two frames to estimate a trajectory from");

  nlohmann::json report;
  const LocalFrame frame(nav.origin);
  std::vector<TrajectoryRow> rows;
  if (mode == "refine") {
    report = RefineFrames(&frames.frames, camera, options, quiet);
    std::set<std::string> nav_only;
    for (const auto& image : report["nav_only"]) nav_only.insert(image.get<std::string>());
    for (const FrameSpec& f : frames.frames)
      rows.push_back({f.image, f.time_s, f.pose, nav_only.count(f.image) ? "nav_only" : ""});
  } else {
    report =
        EstimateFrames(frames.frames, camera, EstimatorOptionsFrom(mode, options, "--mode"), threads, quiet, &rows);
  }
  WriteTrajectoryCsv(out, rows, frame);
  std::printf("trajectory (%s): %zu frames -> %s\n", mode.c_str(), rows.size(), out.c_str());
  if (report_path) {
    report["mode"] = mode;
    std::ofstream file(*report_path);
    if (!file) throw InputError(*report_path, 0, "--report", "cannot write the report file");
    file << report.dump(2) << "\n";
  }
  return 0;
}

}  // namespace seamap::cli
