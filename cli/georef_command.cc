// seamap georef: puts SLAM keyframes (and their point cloud) into real-world
// coordinates from the GPS fixes of a buoy towed on a tether.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/geo/local_frame.h"
#include "core/geo/utm.h"
#include "core/georef/buoy_track.h"
#include "core/georef/depth_profile.h"
#include "core/georef/georef_inputs.h"
#include "core/georef/georef_report.h"
#include "core/georef/georeferencer.h"
#include "core/georef/point_cloud_ply.h"
#include "core/georef/seabed_altitude.h"
#include "core/georef/tum_trajectory.h"
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
Exit 2 for bad input (naming file and line), too few taut keyframes, or degenerate geometry.
)";

std::string Fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

struct Inputs {
  std::vector<std::string> keyframe_files;
  std::string buoy_file, out, report, points, points_out;
  double tether_length_m = 0;
  std::optional<double> depth_m;
  std::string depth_file;
  GeorefOptions options;
  std::optional<LatLon> origin;
  std::optional<UtmZoneId> utm_zone;
  std::string altitude_file;
  bool altitude_from_cloud = false;
};

Inputs ParseInputs(Args& args) {
  Inputs in;
  in.keyframe_files = args.GetAll("keyframes");
  if (in.keyframe_files.empty()) throw InputError("", 0, "--keyframes", "is required: a TUM trajectory file");
  in.buoy_file = args.Require("buoy");
  in.tether_length_m = args.GetDouble("tether-length", NAN);
  if (std::isnan(in.tether_length_m))
    throw InputError("", 0, "--tether-length", "is required: the tether length in metres");
  if (!(in.tether_length_m > 0)) throw InputError("", 0, "--tether-length", "expected a positive length in metres");
  const bool has_depth = args.Get("depth").has_value();
  in.depth_file = args.GetOr("depth-csv", "");
  if (has_depth == !in.depth_file.empty())
    throw InputError("", 0, "--depth", "give either --depth METRES or --depth-csv FILE (exactly one)");
  if (has_depth) {
    in.depth_m = args.GetDouble("depth", 0);
    if (*in.depth_m < 0) throw InputError("", 0, "--depth", "expected a depth >= 0 metres");
    if (*in.depth_m >= in.tether_length_m)
      throw InputError("", 0, "--depth",
                       "depth " + FormatNumber(*in.depth_m) + " m reaches the tether length " +
                           FormatNumber(in.tether_length_m) + " m: the buoy would be straight above, or under water");
  }
  in.out = args.Require("out");
  in.report = args.GetOr("report", "");
  const std::string method = args.GetOr("method", "tether");
  if (method == "triangle")
    in.options.method = GeorefMethod::kTriangle;
  else if (method == "umeyama")
    in.options.method = GeorefMethod::kUmeyama;
  else if (method != "tether")
    throw InputError("", 0, "--method", "expected tether, umeyama or triangle, got '" + method + "'");
  in.options.tether_length_m = in.tether_length_m;
  in.points = args.GetOr("points", "");
  in.points_out = args.GetOr("points-out", "");
  if (in.points.empty() != in.points_out.empty())
    throw InputError("", 0, in.points.empty() ? "--points" : "--points-out", "--points and --points-out go together");
  if (auto origin = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*origin, "--origin");
    in.origin = LatLon{ll.lat, ll.lon};
  }
  in.altitude_file = args.GetOr("altitude-csv", "");
  in.altitude_from_cloud = args.Flag("altitude-from-cloud");
  if (in.altitude_from_cloud && in.points.empty())
    throw InputError("", 0, "--altitude-from-cloud", "needs the point cloud: give --points and --points-out");
  if (in.altitude_from_cloud && !in.altitude_file.empty())
    throw InputError("", 0, "--altitude-from-cloud", "give either --altitude-csv FILE or --altitude-from-cloud");
  if (auto zone = args.Get("utm-zone")) {
    std::string why;
    const auto parsed = ParseUtmZone(*zone, &why);
    if (!parsed || parsed->zone < 1 || parsed->zone > 60)
      throw InputError("", 0, "--utm-zone", "expected a zone 1..60 with N or S, e.g. 33N, got '" + *zone + "'");
    in.utm_zone = UtmZoneId{parsed->zone, parsed->north.value_or(true)};
  }
  return in;
}

// Every keyframe of every sub-map, in time order.
std::vector<const KeyframeGeoref*> NavRows(const std::vector<SubmapGeoref>& submaps) {
  std::vector<const KeyframeGeoref*> rows;
  for (const auto& s : submaps)
    for (const auto& k : s.keyframes) rows.push_back(&k);
  std::stable_sort(rows.begin(), rows.end(), [](auto* a, auto* b) { return a->time_s < b->time_s; });
  return rows;
}

// altitude: per row, or empty for no altitude_m column (a row without one
// gets an empty field, which seamap build skips and lists).
void WriteNav(const std::string& path, const std::vector<const KeyframeGeoref*>& rows, const LocalFrame& frame,
              const std::vector<std::optional<double>>& altitude) {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "--out", "cannot write the file");
  out << "time_s,lat,lon,depth_m,heading_deg,good,sigma_m" << (altitude.empty() ? "" : ",altitude_m") << "\n";
  char line[200];
  for (size_t i = 0; i < rows.size(); ++i) {
    const KeyframeGeoref* k = rows[i];
    const LatLon ll = frame.ToLatLon({k->position_enu_m.x(), k->position_enu_m.y()});
    const double depth = k->depth_m.value_or(-k->position_enu_m.z());
    std::snprintf(line, sizeof line, "%.6f,%.9f,%.9f,%.3f,%.2f,%d,%.3f", k->time_s, ll.lat, ll.lon, depth,
                  k->heading_deg, k->good ? 1 : 0, k->sigma_m);
    out << line;
    if (!altitude.empty()) out << "," << (altitude[i] ? Fixed(*altitude[i], 3) : "");
    out << "\n";
  }
  if (!out) throw InputError(path, 0, "--out", "cannot write the file");
}

// Maps the cloud by the first sub-map's transform into UTM (or local metres
// about --origin); returns the mapped points in the working frame.
std::vector<Eigen::Vector3d> WritePoints(const Inputs& in, const Similarity& fit, const LocalFrame& frame,
                                         const UtmZoneId& zone) {
  PointCloud cloud = ReadPly(in.points);
  const UtmProjection utm(zone);
  std::vector<Eigen::Vector3d> working;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d local = fit.Apply(cloud.Point(i));
    working.push_back(local);
    if (in.origin) {
      cloud.SetPoint(i, local);
    } else {
      const UtmXY xy = utm.Forward(frame.ToLatLon({local.x(), local.y()}));
      cloud.SetPoint(i, {xy.easting, xy.northing, local.z()});
    }
    if (cloud.HasNormals()) cloud.SetNormal(i, fit.rotation * cloud.Normal(i));
  }
  const LatLon o = frame.origin();
  cloud.comments.push_back(in.origin ? "seamap georef: x y z = metres east, north, up (= -depth) about the origin " +
                                           Fixed(o.lat, 9) + "," + Fixed(o.lon, 9) + " (transverse Mercator, WGS84)"
                                     : "seamap georef: x y z = UTM zone " + zone.Name() +
                                           " (EPSG:" + std::to_string(zone.Epsg()) +
                                           ") easting, northing, and up (= -depth), metres, WGS84");
  WritePly(in.points_out, cloud);
  return working;
}

std::string Summary(const SubmapGeoref& s) {
  std::string reasons;
  for (const auto& [r, n] : s.rejected) reasons += (reasons.empty() ? "" : ", ") + std::to_string(n) + " " + r;
  std::string line = s.source + ": " + std::to_string(s.keyframes.size()) + " keyframes, " + std::to_string(s.good) +
                     " good" + (reasons.empty() ? "" : " (not used: " + reasons + ")");
  if (s.fitted)
    line += "; " + s.method + ": scale " + FormatNumber(s.transform.scale) + " m per SLAM unit, residual " +
            Fixed(s.rmse_m, 3) + " m RMS, expected error " + Fixed(s.predicted_rmse_m, 3) + " m (GPS sigma " +
            Fixed(s.gps_sigma_m, 2) + " m, " + Fixed(s.n_eff, 0) + " fixes)";
  return line;
}

}  // namespace

int RunGeoref(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"quiet", "help", "altitude-from-cloud"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  const Inputs in = ParseInputs(args);
  const bool quiet = args.Flag("quiet");
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap georef --help");

  std::vector<std::vector<Keyframe>> keyframes;
  for (const auto& file : in.keyframe_files) keyframes.push_back(ReadTumTrajectory(file));
  const BuoyLog buoy_log = ReadBuoyLog(in.buoy_file);
  std::vector<std::string> warnings = buoy_log.warnings;
  for (const auto& r : buoy_log.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());

  // The working frame: centred on the buoy track (or --origin), metres east, north, up.
  const LatLon median = MedianPosition(buoy_log);
  const LocalFrame frame(in.origin.value_or(median));
  const UtmZoneId zone = in.utm_zone.value_or(UtmZoneFor(median));
  const BuoyTrack buoy = MakeBuoyTrack(buoy_log, frame);

  DepthProfile depth = DepthProfile::Constant(in.depth_m.value_or(0));
  if (!in.depth_file.empty()) {
    const DepthLog log = ReadDepthLog(in.depth_file);
    for (const auto& r : log.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
    warnings.insert(warnings.end(), log.warnings.begin(), log.warnings.end());
    depth = DepthProfile::Samples(log.samples);
  }
  std::optional<DepthProfile> altitude_series;  // read before any output is written
  if (!in.altitude_file.empty()) {
    const DepthLog log = ReadAltitudeLog(in.altitude_file);
    for (const auto& r : log.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
    warnings.insert(warnings.end(), log.warnings.begin(), log.warnings.end());
    altitude_series = DepthProfile::Samples(log.samples);
  }
  GeorefOptions options = in.options;
  options.depth_sigma_m = std::max(options.depth_sigma_m, depth.NoiseSigma());

  std::vector<SubmapGeoref> submaps;
  for (size_t i = 0; i < keyframes.size(); ++i)
    submaps.push_back(GeoreferenceSubmap(in.keyframe_files[i], keyframes[i], buoy, depth, options));

  for (const auto& s : submaps) {
    for (const auto& r : s.resets) warnings.push_back(s.source + ":" + std::to_string(r.line) + ": " + r.why);
    warnings.insert(warnings.end(), s.warnings.begin(), s.warnings.end());
  }
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  GeorefReportContext context{frame.origin(),
                              zone,
                              in.buoy_file,
                              static_cast<int>(buoy_log.fixes.size()),
                              static_cast<int>(buoy_log.rejected.size()),
                              warnings};
  if (!in.report.empty()) {
    std::ofstream report(in.report);
    report << GeorefReport(submaps, context).dump(2) << "\n";
    if (!report) throw InputError(in.report, 0, "--report", "cannot write the report");
  }
  for (const auto& s : submaps)
    if (!quiet || s.degenerate) std::fprintf(stderr, "%s\n", Summary(s).c_str());
  for (const auto& s : submaps)
    if (s.degenerate) throw InputError(s.source, 0, "", "cannot georeference: " + s.reason);

  std::vector<Eigen::Vector3d> cloud;
  if (!in.points.empty()) cloud = WritePoints(in, submaps.front().transform, frame, zone);
  const std::vector<const KeyframeGeoref*> rows = NavRows(submaps);
  std::vector<std::optional<double>> altitude;
  if (altitude_series) {
    for (const KeyframeGeoref* k : rows) altitude.push_back(altitude_series->At(k->time_s));
  } else if (in.altitude_from_cloud) {
    std::vector<Eigen::Vector3d> positions;
    for (const KeyframeGeoref* k : rows) positions.push_back(k->position_enu_m);
    altitude = AltitudeFromCloud(positions, cloud, SeabedAltitudeOptions{});
  }
  const auto missing = std::count(altitude.begin(), altitude.end(), std::nullopt);
  if (missing > 0)
    std::fprintf(stderr, "warning: %s: %ld of %zu keyframes have no altitude (%s); seamap build skips them\n",
                 in.out.c_str(), static_cast<long>(missing), rows.size(),
                 in.altitude_from_cloud ? "fewer than 5 cloud points within 2 m below them"
                                        : "outside the altitude log's span or in a gap over 10 s");
  WriteNav(in.out, rows, frame, altitude);
  int total = 0, good = 0;
  for (const auto& s : submaps) total += static_cast<int>(s.keyframes.size()), good += s.good;
  std::printf("georeferenced %d keyframes (%d good) in %zu sub-map%s -> %s%s%s\n", total, good, submaps.size(),
              submaps.size() == 1 ? "" : "s", in.out.c_str(), in.points.empty() ? "" : ", ", in.points_out.c_str());
  return 0;
}

}  // namespace seamap::cli
