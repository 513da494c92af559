#include "cli/stereo_setup.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/controllers/stereo_locate.h"
#include "core/util/error.h"

namespace seamap::cli {

const char* kLiveStereoHelp =
    "stereo in the dive (as seamap stereo-locate --pairs DIR locates them):\n"
    "  --stereo DIR        stereo pairs (NAME_left.png, NAME_right.png) located as the replay passes each\n"
    "                      pair's time, on the poses the frames were placed with; the objects go to the\n"
    "                      console and the mission as they are found (source stereo, class = the model)\n"
    "  --calib FILE        the rig's stereo.yaml      --model FILE   the object model (stereo-model)\n"
    "  --pair-times FILE   each pair's time (image,time_s); default: from the pair's name\n"
    "  --rig forward|down  --rig-offset X,Y,Z   the left camera on the vehicle (see stereo-locate --help)\n"
    "  --min-inliers N     --max-features N     --method features|icp\n";

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

std::shared_ptr<const StereoLocateOptions> ReadLiveStereo(Args& args) {
  const std::optional<std::string> dir = args.Get("stereo");
  if (!dir) {
    for (const char* option :
         {"calib", "model", "pair-times", "rig", "rig-offset", "method", "min-inliers", "max-features"})
      if (args.Get(option)) throw InputError("", 0, std::string("--") + option, "goes with --stereo DIR");
    return nullptr;
  }
  auto options = std::make_shared<StereoLocateOptions>();
  StereoLocateOptions& o = *options;
  o.pairs_dir = *dir;
  o.calib_path = args.Get("calib").value_or("");
  o.model_path = args.Get("model").value_or("");
  if (o.calib_path.empty()) throw InputError("", 0, "--calib", "is required with --stereo: the rig's stereo.yaml");
  if (o.model_path.empty())
    throw InputError("", 0, "--model", "is required with --stereo: the object model (seamap stereo-model)");
  o.pair_times_path = args.Get("pair-times");
  o.mount = ReadRigMount(args);
  o.method = args.GetOr("method", "features");
  if (o.method != "features" && o.method != "icp")
    throw InputError("", 0, "--method", "expected features or icp, got '" + o.method + "'");
  o.locate.min_inliers = args.GetInt("min-inliers", o.locate.min_inliers);
  o.locate.sift.max_features = args.GetInt("max-features", o.locate.sift.max_features);
  o.quiet = true;
  return options;
}

}  // namespace seamap::cli
