#include "core/sim/survey_path.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kHeadingChord = 0.2;  // metres either side, see HeadingAt

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) {
    cell.erase(0, cell.find_first_not_of(" \t\r"));
    cell.erase(cell.find_last_not_of(" \t\r") + 1);
    cells.push_back(cell);
  }
  return cells;
}

double ParseCell(const std::string& text, const std::string& file, int line, const std::string& field) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw InputError(file, line, field, "expected a finite number in metres, got '" + text + "'");
  return v;
}

}  // namespace

void SurveyPath::Add(const Segment& segment) {
  if (segment.length <= 0) return;
  segments_.push_back(segment);
  cumulative_.push_back(Length() + segment.length);
}

SurveyPath SurveyPath::Lawnmower(double line_length_m, double spacing_m, double min_length_m) {
  if (!(line_length_m > 0)) throw InputError("", 0, "--line-length", "expected a positive length in metres");
  if (!(spacing_m > 0)) throw InputError("", 0, "--line-spacing", "expected a positive spacing in metres");
  SurveyPath path;
  const double r = spacing_m / 2;
  for (int k = 0;; ++k) {
    const double east = k * spacing_m;
    const bool northward = k % 2 == 0;
    Segment line;
    line.start = {east, northward ? 0.0 : line_length_m};
    line.end = {east, northward ? line_length_m : 0.0};
    line.length = line_length_m;
    path.Add(line);
    if (path.Length() >= min_length_m) break;
    // Turn east: over the top after a northward line, under the bottom otherwise.
    Segment turn;
    turn.arc = true;
    turn.centre = {east + r, northward ? line_length_m : 0.0};
    turn.radius = r;
    turn.phi0 = M_PI;
    turn.phi1 = northward ? 0.0 : 2 * M_PI;
    turn.length = M_PI * r;
    path.Add(turn);
  }
  return path;
}

SurveyPath SurveyPath::FromWaypoints(const std::vector<LocalXY>& waypoints) {
  SurveyPath path;
  for (size_t i = 1; i < waypoints.size(); ++i) {
    Segment s;
    s.start = waypoints[i - 1];
    s.end = waypoints[i];
    s.length = std::hypot(s.end.east - s.start.east, s.end.north - s.start.north);
    path.Add(s);
  }
  if (path.segments_.empty()) throw InputError("", 0, "--path", "expected at least two distinct waypoints");
  return path;
}

SurveyPath SurveyPath::LoadCsv(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, 0, "--path", "cannot open the path file");
  std::string line;
  if (!std::getline(in, line)) throw InputError(file, 1, "", "empty file; expected a header with x_m,y_m");
  const auto header = SplitCsv(line);
  const auto column = [&](const std::string& name) {
    auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(file, 1, name, "missing column; expected a header with x_m,y_m");
    return static_cast<size_t>(it - header.begin());
  };
  const size_t cx = column("x_m"), cy = column("y_m");
  std::vector<LocalXY> points;
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto cells = SplitCsv(line);
    if (cells.size() <= std::max(cx, cy))
      throw InputError(file, number, cells.size() <= cx ? "x_m" : "y_m", "missing value");
    points.push_back({ParseCell(cells[cx], file, number, "x_m"), ParseCell(cells[cy], file, number, "y_m")});
  }
  try {
    return FromWaypoints(points);
  } catch (const InputError&) {
    throw InputError(file, 0, "", "expected at least two distinct waypoints");
  }
}

LocalXY SurveyPath::PositionAt(double s) const {
  s = std::clamp(s, 0.0, Length());
  const size_t i = std::min<size_t>(std::lower_bound(cumulative_.begin(), cumulative_.end(), s) - cumulative_.begin(),
                                    segments_.size() - 1);
  const Segment& seg = segments_[i];
  const double f = (s - (cumulative_[i] - seg.length)) / seg.length;
  if (!seg.arc)
    return {seg.start.east + f * (seg.end.east - seg.start.east),
            seg.start.north + f * (seg.end.north - seg.start.north)};
  const double phi = seg.phi0 + f * (seg.phi1 - seg.phi0);
  return {seg.centre.east + seg.radius * std::cos(phi), seg.centre.north + seg.radius * std::sin(phi)};
}

double SurveyPath::HeadingAt(double s) const {
  const LocalXY a = PositionAt(std::max(0.0, s - kHeadingChord));
  const LocalXY b = PositionAt(std::min(Length(), s + kHeadingChord));
  const double deg = std::atan2(b.east - a.east, b.north - a.north) * 180 / M_PI;
  return deg < 0 ? deg + 360 : deg;
}

std::vector<TimedPose> MakeTrajectory(const SurveyPath& path, const TrajectoryOptions& o, uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x7261636b);  // "track"
  std::uniform_real_distribution<double> phase(0, 2 * M_PI);
  double ph[6];
  for (double& p : ph) p = phase(rng);
  const auto wave = [](double t, double period, double phi) { return std::sin(2 * M_PI * t / period + phi); };
  const double alt_mid = (o.altitude_min_m + o.altitude_max_m) / 2;
  const double alt_half = (o.altitude_max_m - o.altitude_min_m) / 2;

  std::vector<TimedPose> poses;
  for (int i = 0; i < o.frames; ++i) {
    TimedPose tp;
    tp.time_s = i / o.fps;
    const double s = o.speed_mps * tp.time_s;
    if (s > path.Length() + 1e-9) break;
    const double t = tp.time_s;
    const LocalXY xy = path.PositionAt(s);
    VehiclePose& p = tp.pose;
    p.east_m = xy.east;
    p.north_m = xy.north;
    p.heading_deg = path.HeadingAt(s);
    // Weights sum to 1 so each value stays within its range.
    p.altitude_m = alt_mid + alt_half * (0.7 * wave(t, 23.0, ph[0]) + 0.3 * wave(t, 9.7, ph[1]));
    p.pitch_deg = o.pitch_amp_deg * (0.75 * wave(t, 9.1, ph[2]) + 0.25 * wave(t, 4.3, ph[3]));
    p.roll_deg = o.roll_amp_deg * (0.75 * wave(t, 6.7, ph[4]) + 0.25 * wave(t, 3.1, ph[5]));
    p.depth_m = o.sea_depth_m - p.altitude_m;
    poses.push_back(tp);
  }
  return poses;
}

std::vector<TimedPose> AddNavigationErrors(const std::vector<TimedPose>& truth, const NavErrorOptions& e,
                                           uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x6e6f697365);  // "noise"
  std::normal_distribution<double> gauss(0, 1);
  const double drift_dir = std::uniform_real_distribution<double>(0, 2 * M_PI)(rng);
  std::vector<TimedPose> out = truth;
  for (TimedPose& tp : out) {
    const double drift = e.drift_m_per_min * tp.time_s / 60;
    tp.pose.east_m += drift * std::sin(drift_dir) + e.position_sigma_m * gauss(rng);
    tp.pose.north_m += drift * std::cos(drift_dir) + e.position_sigma_m * gauss(rng);
    double h = std::fmod(tp.pose.heading_deg + e.heading_sigma_deg * gauss(rng), 360.0);
    tp.pose.heading_deg = h < 0 ? h + 360 : h;
  }
  return out;
}

}  // namespace seamap
