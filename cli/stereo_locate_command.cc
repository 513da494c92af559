// seamap stereo-locate: the camera's pose in the object's frame from stereo pairs.
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/stereo/icp_baseline.h"
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
  --min-inliers N    found rule: inliers per pair (default 12)
  --max-features N   SIFT keypoints per image (default 4000)
)";

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
  options.sift.max_features = args.GetInt("max-features", options.sift.max_features);
  args.RejectUnknown();
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

  LocateResult result;
  if (method == "icp") {
    IcpOptions icp;
    icp.sift = options.sift;
    icp.match = options.match;
    result = LocateObjectIcp(model, calibration, pairs, icp);
  } else {
    result = LocateObject(model, calibration, pairs, options);
  }
  std::ofstream file(out);
  if (!file) throw InputError(out, 0, "--out", "cannot write the pose");
  file << LocateResultToJson(result, model.name).dump(2) << "\n";
  if (result.found) {
    const Eigen::Vector3d c = result.object_from_camera.translation();
    std::printf("found '%s' (%s) in %zu pair(s): camera at %.4f %.4f %.4f m, sigma %.1f mm, RMS %.2f px -> %s\n",
                model.name.c_str(), result.method.c_str(), result.pairs.size(), c.x(), c.y(), c.z(),
                1000 * result.position_sigma_m.norm(), result.joint_rms_px, out.c_str());
  } else {
    std::printf("not found: %s -> %s\n", result.reason.c_str(), out.c_str());
  }
  return 0;
}

}  // namespace seamap::cli
