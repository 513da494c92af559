#include "core/sim/buoy_survey.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/georef/point_cloud_ply.h"
#include "core/georef/tether.h"
#include "core/georef/tether_model.h"
#include "core/georef/tum_trajectory.h"
#include "core/sim/survey_path.h"
#include "core/util/error.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = M_PI / 180.0;
constexpr double kEpochS = 1700000000.0;  // Unix seconds, as SLAM logs them: parse as double
constexpr double kStepS = 0.01;           // the buoy at 100 Hz

void Require(bool ok, const char* option, const std::string& what) {
  if (!ok) throw InputError("", 0, option, what);
}

void Check(const BuoySurveyOptions& o) {
  Require(!o.out_dir.empty(), "--out", "is required: the folder to write the survey to");
  Require(o.pattern == "lawnmower" || o.pattern == "line" || o.pattern == "hover" || o.pattern == "circles" ||
              o.pattern == "spiral" || o.pattern == "transect",
          "--pattern", "expected lawnmower, line, hover, circles, spiral or transect, got '" + o.pattern + "'");
  Require(o.turn_radius_m >= 0 && o.turn_radius_m <= o.line_spacing_m / 2 + 1e-9, "--turn-radius",
          "expected a radius within [0, half the line spacing] metres (0: half the spacing)");
  Require(o.meander_m >= 0, "--meander", "expected an amplitude >= 0 metres");
  Require(o.meander_wavelength_m > 0, "--meander-wavelength", "expected a positive length in metres");
  Require(o.depth_period_s > 0, "--depth-period", "expected a positive time in seconds");
  Require(o.buoy_model == "tractrix" || o.buoy_model == "path", "--buoy-model",
          "expected tractrix or path, got '" + o.buoy_model + "'");
  Require(o.tether_sag >= 0 && o.tether_sag < 0.5, "--tether-sag", "expected a fraction within [0, 0.5)");
  Require(o.wave_height_m >= 0, "--wave-height", "expected a height >= 0 metres");
  Require(o.wave_period_s > 0, "--wave-period", "expected a positive time in seconds");
  Require(std::hypot(o.current_east_mps, o.current_north_mps) < 0.8 * o.speed_mps, "--current-east",
          "expected a current (with --current-north) slower than 0.8 times the vehicle's speed");
  Require(o.multipath_m >= 0, "--multipath-m", "expected a distance >= 0 metres");
  Require(o.gps_outages >= 0 && o.gps_outages <= 100, "--gps-outages", "expected 0 to 100 outages");
  Require(o.gps_outage_s > 0, "--gps-outage", "expected a positive time in seconds");
  Require(o.lines >= 1 && o.lines <= 100, "--lines", "expected 1 to 100 lines");
  Require(o.line_length_m > 0, "--line-length", "expected a positive length in metres");
  Require(o.line_spacing_m > 0, "--line-spacing", "expected a positive spacing in metres");
  Require(o.speed_mps > 0 && o.speed_mps < 5, "--speed", "expected a speed within (0, 5) m/s");
  Require(o.tether_length_m > 0, "--tether-length", "expected a positive length in metres");
  Require(o.depth_m >= 0 && o.depth_m + std::fabs(o.depth_wave_m) < o.tether_length_m, "--depth",
          "expected a depth within [0, tether length), with --depth-wave");
  Require(o.gps_rate_hz > 0 && o.gps_rate_hz <= 100, "--gps-rate", "expected a rate within (0, 100] Hz");
  for (auto [v, name] : {std::pair{o.gps_sigma_m, "--gps-sigma"},
                         {o.gps_correlated_m, "--gps-correlated"},
                         {o.slam_noise_m, "--slam-noise"},
                         {o.depth_noise_m, "--depth-noise"},
                         {o.slack_drift_mps, "--slack-drift"}})
    Require(v >= 0, name, "expected a value >= 0");
  Require(o.gps_tau_s > 0, "--gps-tau", "expected a positive time in seconds");
  Require(o.dropout_fraction >= 0 && o.dropout_fraction < 1, "--dropouts", "expected a fraction within [0, 1)");
  Require(o.multipath_fraction >= 0 && o.multipath_fraction < 1, "--multipath", "expected a fraction within [0, 1)");
  Require(o.keyframe_interval_s >= 0.05, "--keyframe-interval", "expected at least 0.05 s");
  Require(o.submaps >= 1 && o.submaps <= 10, "--submaps", "expected 1 to 10 sub-maps");
  Require(o.cloud_points >= 0, "--cloud-points", "expected a count >= 0");
  Require(o.seabed_depth_m > 0, "--seabed-depth", "expected a positive depth in metres");
}

void PrepareFolder(const BuoySurveyOptions& o) {
  const fs::path out(o.out_dir);
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError(o.out_dir, 0, "--out", "exists and is not a folder");
  if (fs::exists(out) && !fs::is_empty(out) && !o.force)
    throw InputError(o.out_dir, 0, "--out", "folder is not empty; use --force to overwrite it");
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(o.out_dir, 0, "--out", "cannot create the folder: " + ec.message());
}

// The vehicle's horizontal path and the speed it is flown at.
struct Pattern {
  SurveyPath path;
  double speed_mps = 0;
};

SurveyPath Circle(double radius_m, double length_m) {
  std::vector<LocalXY> points;
  const int per_lap = 72;
  const int laps = std::max(1, static_cast<int>(std::ceil(length_m / (2 * M_PI * radius_m))));
  for (int k = 0; k <= laps * per_lap; ++k) {
    const double a = 2 * M_PI * k / per_lap;
    points.push_back({radius_m * std::sin(a), radius_m * (1 - std::cos(a))});
  }
  return SurveyPath::FromWaypoints(points);
}

// Waypoints every 0.2 m along an arc about `centre` from angle a0 to a1 (radians, from east, counter-clockwise).
void AddArc(std::vector<LocalXY>* points, LocalXY centre, double radius, double a0, double a1) {
  const int steps = std::max(2, static_cast<int>(std::ceil(std::fabs(a1 - a0) * radius / 0.2)));
  for (int k = 1; k <= steps; ++k) {
    const double a = a0 + (a1 - a0) * k / steps;
    points->push_back({centre.east + radius * std::cos(a), centre.north + radius * std::sin(a)});
  }
}

void AddLine(std::vector<LocalXY>* points, LocalXY to) {
  const LocalXY from = points->back();
  const int steps =
      std::max(1, static_cast<int>(std::ceil(std::hypot(to.east - from.east, to.north - from.north) / 0.2)));
  for (int k = 1; k <= steps; ++k)
    points->push_back(
        {from.east + (to.east - from.east) * k / steps, from.north + (to.north - from.north) * k / steps});
}

// Lines north then south, `spacing` apart towards the east, joined by turns of radius r (<= spacing / 2):
// a quarter circle, a straight run across, a quarter circle.
std::vector<LocalXY> LawnmowerPoints(int lines, double length, double spacing, double r) {
  std::vector<LocalXY> p{{0, 0}};
  for (int k = 0; k < lines; ++k) {
    const double east = k * spacing;
    const bool north = k % 2 == 0;
    AddLine(&p, {east, north ? length : 0.0});
    if (k + 1 == lines) break;
    const double y = north ? length : 0.0, sign = north ? 1 : -1;
    AddArc(&p, {east + r, y}, r, M_PI, M_PI - sign * M_PI / 2);
    AddLine(&p, {east + spacing - r, y + sign * r});
    AddArc(&p, {east + spacing - r, y}, r, M_PI / 2 * sign, 0);
  }
  return p;
}

// An Archimedean spiral outwards from `inner` metres, arms `spacing` apart, `length` metres long.
std::vector<LocalXY> SpiralPoints(double inner, double spacing, double length) {
  std::vector<LocalXY> p;
  const double b = spacing / (2 * M_PI);
  double a = 0, travelled = 0;
  while (travelled < length) {
    const double r = inner + b * a;
    p.push_back({r * std::cos(a), r * std::sin(a)});
    a += 0.2 / r;
    travelled += 0.2;
  }
  return p;
}

// Each point moved sideways (normal to the track) by amplitude sin(2 pi s / wavelength).
std::vector<LocalXY> Meander(const std::vector<LocalXY>& p, double amplitude, double wavelength) {
  if (amplitude <= 0) return p;
  std::vector<LocalXY> out(p.size());
  double s = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (i > 0) s += std::hypot(p[i].east - p[i - 1].east, p[i].north - p[i - 1].north);
    const size_t a = i > 0 ? i - 1 : i, b = i + 1 < p.size() ? i + 1 : i;
    const double de = p[b].east - p[a].east, dn = p[b].north - p[a].north, d = std::max(std::hypot(de, dn), 1e-9);
    const double off = amplitude * std::sin(2 * M_PI * s / wavelength);
    out[i] = {p[i].east + off * dn / d, p[i].north - off * de / d};
  }
  return out;
}

Pattern MakePattern(const BuoySurveyOptions& o) {
  const double total_m = o.lines * o.line_length_m;
  const double r = o.turn_radius_m > 0 ? o.turn_radius_m : o.line_spacing_m / 2;
  if (o.pattern == "line") return {SurveyPath::FromWaypoints({{0, 0}, {0, total_m}}), o.speed_mps};
  if (o.pattern == "circles") return {Circle(o.line_spacing_m / 3, total_m), o.speed_mps};
  if (o.pattern == "hover") return {Circle(0.5, 0.05 * total_m / o.speed_mps), 0.05};  // drifting on the spot
  std::vector<LocalXY> points;
  if (o.pattern == "spiral")
    points = SpiralPoints(std::max(2 * r, 10.0), o.line_spacing_m, total_m);
  else if (o.pattern == "transect")
    points = LawnmowerPoints(2, total_m / 2, o.line_spacing_m, r);
  else
    points = LawnmowerPoints(o.lines, o.line_length_m, o.line_spacing_m, r);
  return {SurveyPath::FromWaypoints(Meander(points, o.meander_m, o.meander_wavelength_m)), o.speed_mps};
}

Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0, 1);
  Eigen::Quaterniond q(gauss(rng), gauss(rng), gauss(rng), gauss(rng));  // uniform over SO(3)
  return q.normalized().toRotationMatrix();
}

// A level vehicle with the default downward camera: x starboard, y aft, z down.
Eigen::Matrix3d EnuFromCamera(double heading_deg) {
  const double h = heading_deg * kDeg;
  const Eigen::Vector3d forward(std::sin(h), std::cos(h), 0), starboard(std::cos(h), -std::sin(h), 0);
  Eigen::Matrix3d r;
  r.col(0) = starboard;
  r.col(1) = -forward;
  r.col(2) = Eigen::Vector3d(0, 0, -1);
  return r;
}

std::string Line(const char* format, double a, double b, double c) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b, c);
  return buffer;
}

std::string Line(const char* format, double a, double b) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, format, a, b);
  return buffer;
}

}  // namespace

BuoySurveySummary SimulateBuoySurvey(const BuoySurveyOptions& o) {
  Check(o);
  PrepareFolder(o);
  const fs::path out(o.out_dir);
  const LocalFrame frame(o.origin);
  const Pattern pattern = MakePattern(o);
  const double duration = pattern.path.Length() / pattern.speed_mps;
  auto position_at = [&](double t) {
    const LocalXY p = pattern.path.PositionAt(t * pattern.speed_mps);
    return Eigen::Vector2d(p.east, p.north);
  };
  auto heading_at = [&](double t) { return pattern.path.HeadingAt(t * pattern.speed_mps); };
  auto depth_at = [&](double t) { return o.depth_m + o.depth_wave_m * std::sin(2 * M_PI * t / o.depth_period_s); };

  BuoySurveySummary summary;
  summary.duration_s = duration;
  summary.path_length_m = pattern.path.Length();
  summary.reach_m = TetherReach(o.tether_length_m, o.depth_m);

  // The buoy, pulled along at 100 Hz from trailing taut behind the start.
  std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ull + 0x62756f79);  // "buoy"
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> uniform(0, 1);
  // --gps-seed: the fixes' errors from a generator of their own, so that the
  // same survey (path, similarity, keyframes) is drawn with other GPS errors.
  std::mt19937_64 own_gps_rng(o.gps_seed * 0xD1B54A32D192ED03ull + 0x67707321);  // "gps!"
  std::mt19937_64& gps_rng = o.gps_seed ? own_gps_rng : rng;
  const double h0 = heading_at(0) * kDeg;
  TowedBuoy buoy(position_at(0) - (1 - o.tether_sag) * summary.reach_m * Eigen::Vector2d(std::sin(h0), std::cos(h0)));
  const int steps_per_fix = std::max(1, static_cast<int>(std::lround(1.0 / (o.gps_rate_hz * kStepS))));
  const double fix_interval = steps_per_fix * kStepS;
  const double decay = std::exp(-fix_interval / o.gps_tau_s);
  Eigen::Vector2d correlated(gauss(gps_rng), gauss(gps_rng));
  correlated *= o.gps_correlated_m;
  // Waves and outages from a generator of their own: surveys without them stay as they were.
  std::mt19937_64 sea(o.seed * 0x2545F4914F6CDD1Dull + 0x77617665);  // "wave"
  std::uniform_real_distribution<double> sea_uniform(0, 1);
  const double wave_direction = 2 * M_PI * sea_uniform(sea), wave_phase = 2 * M_PI * sea_uniform(sea);
  std::vector<double> outage_start;
  for (int k = 0; k < o.gps_outages; ++k)
    outage_start.push_back(sea_uniform(sea) * std::max(duration - o.gps_outage_s, 0.0));
  const Eigen::Vector2d current(o.current_east_mps, o.current_north_mps);
  std::string buoy_csv = "time_s,lat,lon\n";
  for (long k = 0; k * kStepS <= duration; ++k) {
    const double t = k * kStepS;
    buoy.Drift(current * kStepS);  // taut, the tether then pulls it along v - current
    const double reach = (1 - o.tether_sag) * TetherReach(o.tether_length_m, depth_at(t));
    if (o.buoy_model == "path") {
      // The buoy runs in the vehicle's wake: `reach` metres back along its path (cutting no corner).
      const double s = t * pattern.speed_mps - reach;
      const LocalXY p = pattern.path.PositionAt(std::max(s, 0.0));
      buoy =
          TowedBuoy(Eigen::Vector2d(p.east, p.north) + std::min(s, 0.0) * Eigen::Vector2d(std::sin(h0), std::cos(h0)));
    } else if (!buoy.Step(position_at(t), reach)) {
      buoy.Drift({o.slack_drift_mps * kStepS, 0});
    }
    if (k % steps_per_fix) continue;
    correlated = decay * correlated +
                 std::sqrt(1 - decay * decay) * o.gps_correlated_m * Eigen::Vector2d(gauss(gps_rng), gauss(gps_rng));
    Eigen::Vector2d fix = buoy.position() + Eigen::Vector2d(o.current_offset_m, 0) + correlated +
                          o.gps_sigma_m * Eigen::Vector2d(gauss(gps_rng), gauss(gps_rng));
    const double thrown = uniform(gps_rng), angle = 2 * M_PI * uniform(gps_rng), dropped = uniform(gps_rng);
    if (thrown < o.multipath_fraction) fix += o.multipath_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    fix += 0.5 * o.wave_height_m * std::cos(2 * M_PI * t / o.wave_period_s + wave_phase) *
           Eigen::Vector2d(std::cos(wave_direction), std::sin(wave_direction));
    if (dropped < o.dropout_fraction) continue;
    if (std::any_of(outage_start.begin(), outage_start.end(),
                    [&](double s) { return t >= s && t < s + o.gps_outage_s; }))
      continue;
    const LatLon ll = frame.ToLatLon({fix.x(), fix.y()});
    buoy_csv += Line("%.3f,%.9f,%.9f\n", kEpochS + t + o.clock_offset_s, ll.lat, ll.lon);
    ++summary.fixes;
  }

  // The seabed (depth, positive down) and a sounder's altitude above it.
  auto seabed_depth_at = [&](double e, double n) {
    return o.seabed_depth_m + 0.5 * std::sin(e / 7) * std::cos(n / 11);
  };
  std::string depth_csv = "time_s,depth_m\n", altitude_csv = "time_s,altitude_m\n";
  for (double t = 0; t <= duration + 1; t += 1.0) {
    depth_csv += Line("%.3f,%.4f\n", kEpochS + t, depth_at(t) + o.depth_noise_m * gauss(rng));
    const Eigen::Vector2d p = position_at(t);
    altitude_csv += Line("%.3f,%.4f\n", kEpochS + t, seabed_depth_at(p.x(), p.y()) - depth_at(t));
  }

  // Keyframes at the true poses, every interval +- a third, twice as often in turns.
  struct Truth {
    double t;
    Eigen::Vector3d enu;
    double heading_deg;
  };
  std::vector<Truth> truth;
  for (double t = 0.5; t < duration - 0.5;) {
    const Eigen::Vector2d p = position_at(t);
    truth.push_back({t, {p.x(), p.y(), -depth_at(t)}, heading_at(t)});
    double turn = std::fabs(heading_at(t + 1) - heading_at(t));
    turn = std::min(turn, 360 - turn);
    t += o.keyframe_interval_s * (2.0 / 3 + 2.0 / 3 * uniform(rng)) * (turn > 2 ? 0.5 : 1.0);
  }

  // Sub-maps: consecutive parts, each in its own SLAM frame; 5 s lost between them.
  nlohmann::json submaps = nlohmann::json::array();
  std::string truth_csv = "time_s,lat,lon,x_m,y_m,depth_m,heading_deg\n";
  std::uniform_real_distribution<double> offset(-100, 100);
  Eigen::Matrix3d first_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d first_translation = Eigen::Vector3d::Zero();
  double first_scale = 1;
  const size_t per_part = (truth.size() + o.submaps - 1) / o.submaps;
  for (int part = 0; part < o.submaps; ++part) {
    // World = s R slam + t: s metres per SLAM unit, log-uniform in [0.05, 20].
    const double scale = std::exp(std::log(0.05) + uniform(rng) * (std::log(20.0) - std::log(0.05)));
    const Eigen::Matrix3d rotation = RandomRotation(rng);
    const Eigen::Vector3d slam_offset(offset(rng), offset(rng), offset(rng));
    const Eigen::Vector3d translation = -scale * rotation * slam_offset;
    if (part == 0) first_rotation = rotation, first_translation = translation, first_scale = scale;
    std::vector<Keyframe> keyframes;
    const size_t begin = part * per_part, end = std::min(truth.size(), (part + 1) * per_part);
    for (size_t i = begin; i < end; ++i) {
      const Truth& k = truth[i];
      if (part > 0 && k.t < truth[begin].t + 5) continue;  // tracking lost, then a new map
      const Eigen::Vector3d noisy = k.enu + o.slam_noise_m * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
      Keyframe kf;
      kf.time_s = kEpochS + k.t;
      kf.position_slam = rotation.transpose() * (noisy - translation) / scale;
      kf.world_from_cam = Eigen::Quaterniond(rotation.transpose() * EnuFromCamera(k.heading_deg));
      keyframes.push_back(kf);
      const LatLon ll = frame.ToLatLon({k.enu.x(), k.enu.y()});
      char row[200];
      std::snprintf(row, sizeof row, "%.9f,%.9f,%.9f,%.4f,%.4f,%.4f,%.3f\n", kf.time_s, ll.lat, ll.lon, k.enu.x(),
                    k.enu.y(), -k.enu.z(), k.heading_deg);
      truth_csv += row;
    }
    const std::string name = o.submaps == 1 ? "keyframes.txt" : "keyframes_" + std::to_string(part + 1) + ".txt";
    WriteTumTrajectory((out / name).string(), keyframes,
                       "simulated by seamap simulate-buoy, seed " + std::to_string(o.seed));
    summary.keyframe_files.push_back(name);
    summary.keyframes += static_cast<int>(keyframes.size());
    nlohmann::json r = nlohmann::json::array();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) r.push_back(rotation(a, b));
    submaps.push_back({{"file", name},
                       {"keyframes", keyframes.size()},
                       {"scale", scale},
                       {"rotation", r},
                       {"translation", {translation.x(), translation.y(), translation.z()}}});
  }

  // A seabed under the survey, in the first sub-map's SLAM frame and in truth.
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Truth& k : truth) lo = lo.cwiseMin(k.enu.head<2>()), hi = hi.cwiseMax(k.enu.head<2>());
  std::vector<Eigen::Vector3d> seabed;
  for (int k = 0; k < o.cloud_points; ++k) {
    const double e = lo.x() - 10 + (hi.x() - lo.x() + 20) * uniform(rng);
    const double n = lo.y() - 10 + (hi.y() - lo.y() + 20) * uniform(rng);
    seabed.push_back({e, n, -seabed_depth_at(e, n)});
  }
  WritePly((out / "cloud_truth.ply").string(), [&] {
    PointCloud c = MakePointCloud(seabed, PointCloud::Format::kBinaryLittleEndian);
    c.comments = {"seamap simulate-buoy: the seabed in local metres east, north, up about the origin " +
                  Line("%.9f,%.9f", o.origin.lat, o.origin.lon)};
    return c;
  }());
  PointCloud cloud;
  cloud.format = PointCloud::Format::kBinaryLittleEndian;
  cloud.comments = {"seamap simulate-buoy: the seabed in the first sub-map's SLAM frame"};
  cloud.vertex_properties = {{"x", "float"}, {"y", "float"}, {"z", "float"}, {"intensity", "uchar"}};
  for (const auto& p : seabed) {
    const Eigen::Vector3d slam = first_rotation.transpose() * (p - first_translation) / first_scale;
    cloud.values.insert(cloud.values.end(), {slam.x(), slam.y(), slam.z(), std::floor(256 * uniform(rng))});
  }
  WritePly((out / "cloud.ply").string(), cloud);

  auto write = [&](const char* name, const std::string& text) {
    std::ofstream file(out / name);
    file << text;
    if (!file) throw InputError((out / name).string(), 0, "--out", "cannot write the file");
  };
  write("buoy.csv", buoy_csv);
  write("depth.csv", depth_csv);
  write("altitude.csv", altitude_csv);
  write("truth.csv", truth_csv);
  nlohmann::json j = {{"seed", o.seed},
                      {"origin", {{"lat", o.origin.lat}, {"lon", o.origin.lon}}},
                      {"frame", "local metres east, north, up about the origin (transverse Mercator, WGS84)"},
                      {"similarity", "world = scale * rotation * slam + translation (rotation row-major)"},
                      {"submaps", submaps},
                      {"reach_m", summary.reach_m},
                      {"duration_s", duration},
                      {"path_length_m", summary.path_length_m},
                      {"options",
                       {{"pattern", o.pattern},
                        {"lines", o.lines},
                        {"line_length_m", o.line_length_m},
                        {"line_spacing_m", o.line_spacing_m},
                        {"turn_radius_m", o.turn_radius_m},
                        {"meander_m", o.meander_m},
                        {"meander_wavelength_m", o.meander_wavelength_m},
                        {"speed_mps", pattern.speed_mps},
                        {"depth_m", o.depth_m},
                        {"depth_wave_m", o.depth_wave_m},
                        {"depth_period_s", o.depth_period_s},
                        {"depth_noise_m", o.depth_noise_m},
                        {"tether_length_m", o.tether_length_m},
                        {"slack_drift_mps", o.slack_drift_mps},
                        {"current_offset_m", o.current_offset_m},
                        {"current_east_mps", o.current_east_mps},
                        {"current_north_mps", o.current_north_mps},
                        {"tether_sag", o.tether_sag},
                        {"buoy_model", o.buoy_model},
                        {"wave_height_m", o.wave_height_m},
                        {"wave_period_s", o.wave_period_s},
                        {"multipath_m", o.multipath_m},
                        {"gps_outages", o.gps_outages},
                        {"gps_outage_s", o.gps_outage_s},
                        {"gps_rate_hz", o.gps_rate_hz},
                        {"gps_sigma_m", o.gps_sigma_m},
                        {"gps_correlated_m", o.gps_correlated_m},
                        {"gps_tau_s", o.gps_tau_s},
                        {"dropout_fraction", o.dropout_fraction},
                        {"multipath_fraction", o.multipath_fraction},
                        {"clock_offset_s", o.clock_offset_s},
                        {"keyframe_interval_s", o.keyframe_interval_s},
                        {"slam_noise_m", o.slam_noise_m},
                        {"submaps", o.submaps},
                        {"cloud_points", o.cloud_points},
                        {"seabed_depth_m", o.seabed_depth_m}}}};
  if (o.gps_seed) j["gps_seed"] = o.gps_seed;
  write("truth.json", j.dump(2) + "\n");
  return summary;
}

}  // namespace seamap
