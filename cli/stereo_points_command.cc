// seamap stereo-points: a stereo rig's pairs as seabed points for the height model.
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/enhance_setup.h"
#include "cli/stereo_setup.h"
#include "core/controllers/stereo_seabed.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage =
    R"(usage: seamap stereo-points --calib stereo.yaml --pairs DIR --nav FILE --out points.csv [options]
Matches and triangulates every stereo pair of DIR, places its points at the pair's time on the
vehicle's navigation and writes them as seabed points (pair, lat, lon, up_m, sigma_up_m: metres up,
from the sea surface when the navigation has depth_m) for build --terrain --terrain-points FILE.
  --pair-times FILE  each pair's time (image,time_s); without it, from the pair's name (as stereo-locate)
  --rig forward|down the left camera looks along the bow (default) or down, image top to the bow
  --rig-offset X,Y,Z the left camera in the vehicle's frame, m (x forward, y starboard, z down)
  --origin LAT,LON   origin of the navigation's local x_m/y_m positions
  --max-sigma-up M   leave out points whose height is less certain than this (default 0.02)
  --max-relief M     leave out points further than this from the plane at the navigation's altitude
                     (default 1.5, as build --max-relief)
  --max-points N     at most N points per pair, the strongest first (default 3000)
  --max-features N   SIFT keypoints per image (default 4000)
  --feature-enhance off|auto|LIST  enhance the pairs before their features are detected (seed 004;
                     auto keeps the chain that raises the left/right inliers, if any; default off)
  --quiet            no progress bar
)";

}  // namespace

int RunStereoPoints(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "quiet"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  StereoPointsOptions o;
  o.calib_path = args.Require("calib");
  o.pairs_dir = args.Require("pairs");
  o.nav_path = args.Require("nav");
  o.out = args.Require("out");
  o.pair_times_path = args.Get("pair-times");
  if (auto v = args.Get("origin")) {
    const LatLonArg origin = ParseLatLon(*v, "--origin");
    o.origin = LatLon{origin.lat, origin.lon};
  }
  o.mount = ReadRigMount(args);
  o.points.max_sigma_up_m = args.GetDouble("max-sigma-up", o.points.max_sigma_up_m);
  o.points.max_relief_m = args.GetDouble("max-relief", o.points.max_relief_m);
  o.points.max_points_per_pair = args.GetInt("max-points", o.points.max_points_per_pair);
  o.sift.max_features = args.GetInt("max-features", o.sift.max_features);
  o.feature_enhance = ReadFeatureEnhance(args);
  o.quiet = args.Flag("quiet");
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap stereo-points --help");
  o.Check();
  const StereoPointsReport report = WriteStereoSeabedPoints(o);
  for (const std::string& why : report.skipped) std::printf("  skipped %s\n", why.c_str());
  std::printf("%ld seabed points from %d of %d pairs (enhancement: %s) -> %s\n", report.points, report.used,
              report.pairs, report.chain.c_str(), o.out.c_str());
  return 0;
}

}  // namespace seamap::cli
