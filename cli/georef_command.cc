// seamap georef: puts SLAM keyframes (and their point cloud) into real-world
// coordinates from the GPS fixes of a buoy towed on a tether.
#include <cmath>
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/controllers/buoy_georef.h"
#include "core/geo/utm.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage =
    R"(usage: seamap georef --keyframes FILE --buoy FILE --tether-length M (--depth M | --depth-csv FILE)
                    --out nav.csv [options]
Georeferences SLAM keyframes with the GPS fixes of a buoy towed on a tether.
  --keyframes FILE    TUM trajectory: 'timestamp tx ty tz qx qy qz qw' a line, camera-to-world;
                      repeat for sub-maps (SLAM resets): each gets its own transform
  --map MAP           instead of --keyframes: the mission's trajectory (the poses its frames were
                      placed with, e.g. replay --nav-mode vo's), its local frame as the SLAM frame
  --buoy FILE         CSV time_s,lat,lon (or easting,northing,zone); optional sigma_m, hdop, fix_quality
  --tether-length M   tether length, metres
  --depth M           constant vehicle depth, metres      --depth-csv FILE   CSV time_s,depth_m
  --out FILE          nav.csv: time_s,lat,lon,depth_m,heading_deg,good,sigma_m, one row per keyframe
                      (sigma_m: its predicted horizontal error, 2D RMS; 0 where the method has none)
  --report FILE       report.json: transform, residuals, good keyframes and why the others are not,
                      predicted errors, per sub-map figures
  --method M          tether (default: similarity, tether reach and the buoy's way of following
                      fitted jointly to every fix, slack stretches with a widened noise) | umeyama
                      (weighted similarity over the taut keyframes' targets, outliers rejected) |
                      triangle (the paper: largest triangle of good keyframes, rigid SVD)
  --points FILE       PLY point cloud in the (first) SLAM frame ...
  --points-out FILE   ... written georeferenced: UTM easting, northing, up (metres, doubles)
  --origin LAT,LON    centre of the working frame; the cloud is then written in local metres
                      east, north, up about it instead of UTM
  --utm-zone Z        UTM zone for the cloud, e.g. 33N (default: from the buoy's median position)
  --altitude-csv FILE CSV time_s,altitude_m (sounder or DVL): nav.csv gets an altitude_m column,
                      which seamap build needs
  --altitude-from-cloud  altitude_m from the georeferenced cloud (--points) below each keyframe
  --clock-sigma S     how well the fixes' clock is known to agree with the keyframes', seconds
                      (default 1) ...
  --sag-sigma F       ... and how much the tether may sag, a share of its reach (default 0.02):
                      what the estimate assumes where the geometry cannot see the buoy's distance
                      behind (a spiral, legs all flown one way); 0 where known
Exit 2 for bad input (naming file and line), too few taut keyframes, or degenerate geometry.
)";

// The options as the command line gives them; checked (BuoyGeorefOptions::Check)
// before any other argument is looked at.
BuoyGeorefOptions ParseInputs(Args& args) {
  BuoyGeorefOptions in;
  in.keyframe_files = args.GetAll("keyframes");
  in.map_path = args.GetOr("map", "");
  if (in.keyframe_files.empty() && in.map_path.empty())
    throw InputError("", 0, "--keyframes", "is required: a TUM trajectory file (or --map MAP: a mission's trajectory)");
  in.buoy_file = args.Require("buoy");
  in.tether_length_m = args.GetDouble("tether-length", NAN);
  if (std::isnan(in.tether_length_m))
    throw InputError("", 0, "--tether-length", "is required: the tether length in metres");
  if (args.Get("depth")) in.depth_m = args.GetDouble("depth", 0);
  in.depth_file = args.GetOr("depth-csv", "");
  in.out = args.Require("out");
  in.report = args.GetOr("report", "");
  const std::string method = args.GetOr("method", "tether");
  if (method == "triangle")
    in.georef.method = GeorefMethod::kTriangle;
  else if (method == "umeyama")
    in.georef.method = GeorefMethod::kUmeyama;
  else if (method != "tether")
    throw InputError("", 0, "--method", "expected tether, umeyama or triangle, got '" + method + "'");
  in.georef.tether_length_m = in.tether_length_m;
  in.points = args.GetOr("points", "");
  in.points_out = args.GetOr("points-out", "");
  if (auto origin = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*origin, "--origin");
    in.origin = LatLon{ll.lat, ll.lon};
  }
  in.altitude_file = args.GetOr("altitude-csv", "");
  in.altitude_from_cloud = args.Flag("altitude-from-cloud");
  if (auto zone = args.Get("utm-zone")) {
    std::string why;
    const auto parsed = ParseUtmZone(*zone, &why);
    if (!parsed || parsed->zone < 1 || parsed->zone > 60)
      throw InputError("", 0, "--utm-zone", "expected a zone 1..60 with N or S, e.g. 33N, got '" + *zone + "'");
    in.utm_zone = UtmZoneId{parsed->zone, parsed->north.value_or(true)};
  }
  in.georef.clock_sigma_s = args.GetDouble("clock-sigma", in.georef.clock_sigma_s);
  in.georef.sag_sigma = args.GetDouble("sag-sigma", in.georef.sag_sigma);
  in.quiet = args.Flag("quiet");
  in.Check();
  return in;
}

}  // namespace

int RunGeoref(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"quiet", "help", "altitude-from-cloud"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  BuoyGeorefOptions in = ParseInputs(args);
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap georef --help");
  const BuoyGeorefResult done = BuoyGeoref(in).Run();
  std::printf("georeferenced %d keyframes (%d good) in %d sub-map%s -> %s%s%s\n", done.keyframes, done.good,
              done.submaps, done.submaps == 1 ? "" : "s", in.out.c_str(), in.points.empty() ? "" : ", ",
              in.points_out.c_str());
  return 0;
}

}  // namespace seamap::cli
