#include "core/controllers/buoy_georef.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/controllers/mission_trajectory_io.h"
#include "core/geo/local_frame.h"
#include "core/geo/rotation.h"
#include "core/georef/buoy_track.h"
#include "core/georef/depth_profile.h"
#include "core/georef/georef_inputs.h"
#include "core/georef/georef_report.h"
#include "core/georef/georeferencer.h"
#include "core/georef/point_cloud_ply.h"
#include "core/georef/seabed_altitude.h"
#include "core/georef/tum_trajectory.h"
#include "core/nav/nav_values.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace seamap {
namespace {

std::string Fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
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
std::vector<Eigen::Vector3d> WritePoints(const BuoyGeorefOptions& in, const Similarity& fit, const LocalFrame& frame,
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

void BuoyGeorefOptions::Check() const {
  if (keyframe_files.empty() && map_path.empty() && keyframes_source.empty())
    throw InputError("", 0, "--keyframes", "is required: a TUM trajectory file (or --map MAP: a mission's trajectory)");
  if (!keyframe_files.empty() && !map_path.empty())
    throw InputError("", 0, "--map", "and --keyframes: give one trajectory to georeference");
  if (!(tether_length_m > 0)) throw InputError("", 0, "--tether-length", "expected a positive length in metres");
  if ((depth_m.has_value() + !depth_file.empty() + !depth_samples.empty()) != 1)
    throw InputError("", 0, "--depth", "give either --depth METRES or --depth-csv FILE (exactly one)");
  if (depth_m) {
    if (*depth_m < 0) throw InputError("", 0, "--depth", "expected a depth >= 0 metres");
    if (*depth_m >= tether_length_m)
      throw InputError("", 0, "--depth",
                       "depth " + FormatNumber(*depth_m) + " m reaches the tether length " +
                           FormatNumber(tether_length_m) + " m: the buoy would be straight above, or under water");
  }
  if (points.empty() != points_out.empty())
    throw InputError("", 0, points.empty() ? "--points" : "--points-out", "--points and --points-out go together");
  if (altitude_from_cloud && points.empty())
    throw InputError("", 0, "--altitude-from-cloud", "needs the point cloud: give --points and --points-out");
  if (!(georef.clock_sigma_s >= 0 && georef.clock_sigma_s <= 60))
    throw InputError("", 0, "--clock-sigma", "expected seconds in [0, 60], got " + FormatNumber(georef.clock_sigma_s));
  if (!(georef.sag_sigma >= 0 && georef.sag_sigma <= 0.5))
    throw InputError("", 0, "--sag-sigma",
                     "expected a share of the reach in [0, 0.5], got " + FormatNumber(georef.sag_sigma));
  if (altitude_from_cloud && !altitude_file.empty())
    throw InputError("", 0, "--altitude-from-cloud", "give either --altitude-csv FILE or --altitude-from-cloud");
}

BuoyGeoref::BuoyGeoref(BuoyGeorefOptions options) : options_(std::move(options)) {
  options_.Check();
}

BuoyGeorefResult BuoyGeoref::Run() {
  const BuoyGeorefOptions& in = options_;
  std::vector<std::vector<Keyframe>> keyframes;
  for (const auto& file : in.keyframe_files) keyframes.push_back(ReadTumTrajectory(file));
  std::vector<std::string> sources = in.keyframe_files;
  if (!in.map_path.empty()) {
    keyframes.push_back(MissionKeyframes(*OpenExistingMap(in.map_path, /*writable=*/false), in.map_path));
    sources.push_back(in.map_path);
  }
  if (!in.keyframes_source.empty()) {
    keyframes.push_back(in.keyframes);
    sources.push_back(in.keyframes_source);
  }
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
  if (!in.depth_samples.empty()) depth = DepthProfile::Samples(in.depth_samples);
  std::optional<DepthProfile> altitude_series;  // read before any output is written
  if (!in.altitude_file.empty()) {
    const DepthLog log = ReadAltitudeLog(in.altitude_file);
    for (const auto& r : log.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
    warnings.insert(warnings.end(), log.warnings.begin(), log.warnings.end());
    altitude_series = DepthProfile::Samples(log.samples);
  }
  GeorefOptions options = in.georef;
  options.depth_sigma_m = std::max(options.depth_sigma_m, depth.NoiseSigma());

  std::vector<SubmapGeoref> submaps;
  for (size_t i = 0; i < keyframes.size(); ++i)
    submaps.push_back(GeoreferenceSubmap(sources[i], keyframes[i], buoy, depth, options));

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
    if (!in.quiet || s.degenerate) std::fprintf(stderr, "%s\n", Summary(s).c_str());
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
  if (!in.out.empty()) WriteNav(in.out, rows, frame, altitude);
  BuoyGeorefResult result;
  for (const auto& s : submaps) result.keyframes += static_cast<int>(s.keyframes.size()), result.good += s.good;
  result.submaps = static_cast<int>(submaps.size());
  result.fits = std::move(submaps);
  result.working_origin = frame.origin();
  return result;
}

}  // namespace seamap
