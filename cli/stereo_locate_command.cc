// seamap stereo-locate: the camera's pose in the object's frame from stereo pairs.
#include <cmath>
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
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
where the object is on the Earth (with --nav and --time):
  --nav FILE         the vehicle's navigation, as seamap build reads it
  --time T           when the first pair used was taken, in the navigation's clock (s)
  --rig forward|down the left camera looks along the bow (default) or down, image top to the bow
  --rig-offset X,Y,Z the left camera in the vehicle's frame, m (x forward, y starboard, z down)
  --map MAP          also store the object in the mission as a detection (source "stereo",
                     class = the model's name, heading and depth), replacing its earlier location
)";

RigMount ReadRigMount(Args& args) {
  RigMount mount;
  mount.looking = ParseLooking(args.GetOr("rig", "forward"), "--rig");
  if (auto text = args.Get("rig-offset")) {
    double x = 0, y = 0, z = 0;
    char end = 0;
    if (std::sscanf(text->c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &end) != 3 || !std::isfinite(x + y + z) ||
        std::abs(x) + std::abs(y) + std::abs(z) > 100)
      throw InputError("", 0, "--rig-offset", "expected X,Y,Z in metres (each within 100 m), got '" + *text + "'");
    mount.offset_m = {x, y, z};
  }
  return mount;
}

}  // namespace

int RunStereoLocate(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "no-tie-points"});
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
  options.nav_path = args.Get("nav");
  options.map_path = args.Get("map");
  if (args.Get("time")) options.time_s = args.GetDouble("time", 0);
  options.mount = ReadRigMount(args);
  args.RejectUnknown();
  options.Check();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap stereo-locate --help");

  StereoLocate locator(options);
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
