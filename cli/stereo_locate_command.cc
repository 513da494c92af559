// seamap stereo-locate: the camera's pose in the object's frame from stereo pairs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/mission/detection_book.h"
#include "core/mission/mission_metadata.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/nav/nav_series.h"
#include "core/stereo/icp_baseline.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/object_locator.h"
#include "core/tiles/tile_store.h"
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
  const std::string calib_path = args.Require("calib"), model_path = args.Require("model");
  const std::string pairs_dir = args.Require("pairs"), out = args.Require("out");
  const int views = args.GetInt("views", 1);
  if (views < 1) throw InputError("", 0, "--views", "expected a positive number of pairs");
  const std::string method = args.GetOr("method", "features");
  if (method != "features" && method != "icp") throw InputError("", 0, "--method", "expected features or icp");
  LocateOptions options;
  options.tie_points = !args.Flag("no-tie-points");
  options.min_inliers = args.GetInt("min-inliers", options.min_inliers);
  options.min_tie_points = args.GetInt("min-tie-points", options.min_tie_points);
  if (const auto motion = args.Get("motion")) options.motion = ReadRigMotion(*motion);
  options.sift.max_features = args.GetInt("max-features", options.sift.max_features);
  const std::optional<std::string> nav_path = args.Get("nav"), map_path = args.Get("map");
  const std::optional<std::string> time_text = args.Get("time");
  const double time_s = args.GetDouble("time", 0);
  const RigMount mount = ReadRigMount(args);
  args.RejectUnknown();
  if (map_path && !nav_path) throw InputError("", 0, "--map", "needs --nav and --time: where the vehicle was");
  if (nav_path.has_value() != time_text.has_value())
    throw InputError("", 0, nav_path ? "--time" : "--nav", "--nav and --time go together");
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap stereo-locate --help");

  const StereoCalibration calibration = LoadStereoCalibration(calib_path);
  const ObjectModel model = LoadObjectModel(model_path);
  if (model.image_size != calibration.image_size)
    throw InputError(model_path, 0, "calibration.image_size",
                     cv::format("the model was built from %dx%d images, %s is for %dx%d", model.image_size.width,
                                model.image_size.height, calib_path.c_str(), calibration.image_size.width,
                                calibration.image_size.height));
  if (std::abs(model.fx_px / calibration.K1(0, 0) - 1) > 0.02 ||
      std::abs(model.baseline_m / cv::norm(calibration.T) - 1) > 0.02)
    std::fprintf(stderr, "seamap stereo-locate: warning: %s was built with another rig (fx %.0f px, baseline %.3f m)\n",
                 model_path.c_str(), model.fx_px, model.baseline_m);
  std::vector<PairFiles> files = ListStereoPairs(pairs_dir);
  if (static_cast<int>(files.size()) < views)
    throw InputError(pairs_dir, 0, "--views",
                     cv::format("asked for %d pairs, the folder has %zu", views, files.size()));
  files.resize(views);
  std::vector<LoadedPair> pairs;
  for (const PairFiles& f : files) pairs.push_back(LoadStereoPair(f, calibration.image_size, calib_path));

  // Where the vehicle was, before the (slow) search: bad navigation is reported first.
  std::unique_ptr<TileStore> store = map_path ? OpenExistingMap(*map_path, /*writable=*/true) : nullptr;
  // The mission's origin: the navigation's local frame, and so the detection's position_m, is the mission's.
  const std::optional<LatLon> origin =
      store ? std::optional<LatLon>(RequireMissionOrigin(ReadMissionMetadata(*store), *map_path)) : std::nullopt;
  std::optional<VehiclePose> vehicle;
  std::optional<LocalFrame> frame;
  if (nav_path) {
    NavReadOptions nav_options;
    nav_options.origin = origin;
    const NavTable nav = ReadNavigation(*nav_path, nav_options);
    if (!nav.has_times)
      throw InputError(*nav_path, 0, "time_s", "the navigation has no times to interpolate at --time");
    // Sorted by time, as build places its frames: unsorted navigation gives the same pose.
    const NavSeries series(nav.records);
    vehicle = series.PoseAt(time_s);
    if (!vehicle)
      throw InputError(
          *nav_path, 0, "--time",
          cv::format("%.3f s is outside the navigation's times (%.3f to %.3f s)", time_s,
                     series.empty() ? 0 : series.first_time_s(), series.empty() ? 0 : series.last_time_s()));
    frame.emplace(nav.origin);
  }

  LocateResult result;
  if (method == "icp") {
    IcpOptions icp;
    icp.sift = options.sift;
    icp.match = options.match;
    result = LocateObjectIcp(model, calibration, pairs, icp);
  } else {
    result = LocateObject(model, calibration, pairs, options);
  }
  nlohmann::json pose_json = LocateResultToJson(result, model.name);
  std::optional<PlacedObject> placed;
  if (result.found && vehicle) {
    placed = PlaceObject(result.object_from_camera, mount, *vehicle, *frame);
    pose_json["geo"] = {{"lat", placed->position.lat},
                        {"lon", placed->position.lon},
                        {"depth_m", placed->depth_m},
                        {"heading_deg", placed->heading_deg},
                        {"time_s", time_s}};
  }
  std::ofstream file(out);
  if (!file) throw InputError(out, 0, "--out", "cannot write the pose");
  file << pose_json.dump(2) << "\n";
  if (placed) {
    std::printf("object at %.7f %.7f, %.3f m deep, heading %.2f deg\n", placed->position.lat, placed->position.lon,
                placed->depth_m, placed->heading_deg);
    if (store) {
      Detection d;
      d.class_name = model.name;
      d.source = "stereo";
      d.model = std::filesystem::path(model_path).filename().string();
      d.score = 1;
      d.position = placed->position;
      d.position_m = std::array<double, 2>{placed->local.east, placed->local.north};  // the mission's frame
      d.heading_deg = placed->heading_deg;
      d.depth_m = placed->depth_m;
      d.time_s = time_s;
      d.status = "unconfirmed";
      // Located again within 10 cm (same model file): the same detection, its review kept.
      d = PublishFound(*store, {d}, d.model, {d.class_name})[0];
      store->Flush();
      std::printf("stored as detection %lld in %s\n", static_cast<long long>(d.id), map_path->c_str());
    }
  }
  if (result.found) {
    const Eigen::Vector3d c = result.object_from_camera.translation();
    std::printf(
        "found '%s' (%s) in %zu pair(s): camera at %.4f %.4f %.4f m (sigma %.1f mm), object points sigma %.2f mm, "
        "RMS %.2f px -> %s\n",
        model.name.c_str(), result.method.c_str(), result.pairs.size(), c.x(), c.y(), c.z(),
        1000 * result.position_sigma_m.norm(), 1000 * result.point_sigma_m, result.joint_rms_px, out.c_str());
  } else {
    std::printf("not found: %s -> %s\n", result.reason.c_str(), out.c_str());
  }
  return 0;
}

}  // namespace seamap::cli
