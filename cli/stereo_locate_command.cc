// seamap stereo-locate: the camera's pose in the object's frame from stereo pairs.
#include <cmath>
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/enhance_setup.h"
#include "cli/stereo_setup.h"
#include "core/controllers/stereo_locate.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/object_locator.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage =
    R"(usage: seamap stereo-locate --calib stereo.yaml --model object.json --pairs DIR --out pose.json [options]
Recognises the modelled object in stereo pairs and writes the left camera's pose in the object's
frame (object_from_camera of the first pair used), per-pair diagnostics and the uncertainty;
found: false (exit 0) when the object is not recognised.
  --views N          use the first N pairs of DIR (sorted by name) jointly (default 1)
  --method M         features (default) or icp (the baseline: OpenCV surface_matching ICP)
  --no-tie-points    joint solution without points matched between the pairs
  --min-tie-points N a later pair joins only when N points tie it to the others (default 10)
  --motion FILE      the rig's motion between the pairs from the vehicle's navigation (motion.json:
                     world_from_camera per pair, sigma_m, sigma_deg): holds the joint solution to it
  --min-inliers N    found rule: inliers per pair (default 12)
  --max-features N   SIFT keypoints per image (default 4000)
  --feature-enhance off|auto|LIST  enhance the pairs before their features are detected (seed 004;
                     LIST as seamap enhance --ops): auto tries a few chains on the first pairs and keeps
                     the one that raises the left/right inliers, if any (default off); build the model
                     with the same chain (stereo-model --feature-enhance)
where the object is on the Earth (a trajectory: --nav, or --map alone):
  --nav FILE         the vehicle's navigation, as seamap build reads it (a trajectory.csv too)
  --map MAP          the mission: its trajectory (the poses its frames were placed with, refined or
                     estimated where they were) unless --nav is given; the object is stored in it as a
                     detection (source "stereo", class = the model's name, heading and depth),
                     replacing its earlier location
  --time T           when the first pair used was taken, in the trajectory's clock (s)
  --rig forward|down the left camera looks along the bow (default) or down, image top to the bow
  --rig-offset X,Y,Z the left camera in the vehicle's frame, m (x forward, y starboard, z down)
a dive (a trajectory and no --time): every pair of DIR is located on its own at its own time, placed
on the trajectory (a pair outside its times is reported and skipped); --out gets every sighting
(the pose file's fields, geo) and a summary (objects: sightings, mean position, spread)
  --pair-times FILE  each pair's time: a CSV with image (the pair's NAME or an image file) and time_s;
                     without it, from the pair's name: a UTC stamp YYYYMMDD_HHMMSS[_mmm] or seconds
                     (NAME_12.500, t12.5, 12.5s)
  --quiet            no progress bar
)";

// Every pair of a dive: a line per sighting, the summary, the mission's objects.
int RunDive(StereoLocate& locator, const StereoLocateOptions& options) {
  const StereoDive dive = locator.RunDive();
  std::printf("dive: '%s' on %s\n", dive.model_name.c_str(), dive.trajectory.c_str());
  for (const StereoSighting& s : dive.sightings) {
    if (!s.skipped.empty())
      std::printf("  %s: skipped, %s\n", s.pair.c_str(), s.skipped.c_str());
    else if (!s.placed)
      std::printf("  %s at %.3f s: not found (%s)\n", s.pair.c_str(), *s.time_s, s.result.reason.c_str());
    else
      std::printf("  %s at %.3f s: object at %.7f %.7f, %.3f m deep, heading %.2f deg (points sigma %.2f mm)\n",
                  s.pair.c_str(), *s.time_s, s.placed->position.lat, s.placed->position.lon, s.placed->depth_m,
                  s.placed->heading_deg, 1000 * s.result.point_sigma_m);
  }
  const nlohmann::json& sum = dive.summary;
  std::printf("%d pairs: %d found, %d not found, %d outside the trajectory's times\n", sum["pairs"].get<int>(),
              sum["found"].get<int>(), sum["not_found"].get<int>(), sum["skipped"].get<int>());
  for (const auto& object : sum["objects"])
    std::printf("object at %.7f %.7f, %.3f m deep: %d sightings, spread %.1f mm RMS (max %.1f mm)\n",
                object["lat"].get<double>(), object["lon"].get<double>(), object["depth_m"].get<double>(),
                object["sightings"].get<int>(), 1000 * object["spread_rms_m"].get<double>(),
                1000 * object["spread_max_m"].get<double>());
  if (options.map_path) {
    const std::vector<long long> ids = locator.StoreDetections(dive);
    std::printf("stored %zu object(s) as detections in %s\n", ids.size(), options.map_path->c_str());
  }
  std::printf("-> %s\n", options.out.c_str());
  return 0;
}

}  // namespace

int RunStereoLocate(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "no-tie-points", "quiet"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  StereoLocateOptions options;
  options.calib_path = args.Require("calib");
  options.model_path = args.Require("model");
  options.pairs_dir = args.Require("pairs");
  options.out = args.Require("out");
  options.views = args.GetInt("views", 1);
  options.method = args.GetOr("method", "features");
  options.Check();  // --views and --method before the motion file is read (--nav and --map come later)
  LocateOptions& locate = options.locate;
  locate.tie_points = !args.Flag("no-tie-points");
  locate.min_inliers = args.GetInt("min-inliers", locate.min_inliers);
  locate.min_tie_points = args.GetInt("min-tie-points", locate.min_tie_points);
  if (const auto motion = args.Get("motion")) locate.motion = ReadRigMotion(*motion);
  locate.sift.max_features = args.GetInt("max-features", locate.sift.max_features);
  options.feature_enhance = ReadFeatureEnhance(args);
  options.nav_path = args.Get("nav");
  options.map_path = args.Get("map");
  if (args.Get("time")) options.time_s = args.GetDouble("time", 0);
  options.pair_times_path = args.Get("pair-times");
  options.quiet = args.Flag("quiet");
  options.mount = ReadRigMount(args);
  args.RejectUnknown();
  options.Check();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap stereo-locate --help");

  StereoLocate locator(options);
  if (options.Dive()) return RunDive(locator, options);
  const StereoLocation located = locator.Run();
  const LocateResult& result = located.result;
  if (const auto& placed = located.placed) {
    std::printf("object at %.7f %.7f, %.3f m deep, heading %.2f deg\n", placed->position.lat, placed->position.lon,
                placed->depth_m, placed->heading_deg);
    if (options.map_path)
      std::printf("stored as detection %lld in %s\n", locator.StoreDetection(located), options.map_path->c_str());
  }
  if (result.found) {
    const Eigen::Vector3d c = result.object_from_camera.translation();
    std::printf(
        "found '%s' (%s) in %zu pair(s): camera at %.4f %.4f %.4f m (sigma %.1f mm), object points sigma %.2f mm, "
        "RMS %.2f px -> %s\n",
        located.model_name.c_str(), result.method.c_str(), result.pairs.size(), c.x(), c.y(), c.z(),
        1000 * result.position_sigma_m.norm(), 1000 * result.point_sigma_m, result.joint_rms_px, options.out.c_str());
  } else {
    std::printf("not found: %s -> %s\n", result.reason.c_str(), options.out.c_str());
  }
  return 0;
}

}  // namespace seamap::cli
