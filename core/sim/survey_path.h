#pragma once
// The simulated vehicle's track: a lawnmower pattern or a custom waypoint
// path, sampled in time into exact poses with smooth altitude, pitch and roll
// variations; plus the navigation errors a real system would add.
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"

namespace seamap {

// A planar path parameterised by arc length (metres), made of straight
// segments and circular arcs.
class SurveyPath {
 public:
  // Lines `line_length_m` long running north then south, `spacing_m` apart
  // towards the east, joined by semicircular turns, starting at (0, 0); as
  // many lines as needed for the path to be at least `min_length_m` long.
  static SurveyPath Lawnmower(double line_length_m, double spacing_m, double min_length_m);
  // Straight segments through the waypoints (at least two, not all equal).
  static SurveyPath FromWaypoints(const std::vector<LocalXY>& waypoints);
  // CSV with a header containing x_m,y_m (east, north metres); other columns
  // are ignored. Throws InputError naming file, line and column.
  static SurveyPath LoadCsv(const std::string& path);

  double Length() const { return cumulative_.empty() ? 0 : cumulative_.back(); }
  // Clamped to [0, Length()].
  LocalXY PositionAt(double s) const;
  // Degrees clockwise from north in [0, 360): direction of the chord between
  // s - 0.2 m and s + 0.2 m, which is the exact tangent on lines and arcs and
  // rounds the corners of waypoint paths.
  double HeadingAt(double s) const;

 private:
  struct Segment {
    bool arc = false;
    LocalXY start, end;                     // straight segment
    LocalXY centre;                         // arc
    double radius = 0, phi0 = 0, phi1 = 0;  // arc angles (radians, from east, counter-clockwise)
    double length = 0;
  };
  void Add(const Segment& segment);
  std::vector<Segment> segments_;
  std::vector<double> cumulative_;  // path length at the end of each segment
};

struct TrajectoryOptions {
  double speed_mps = 0.5;
  double fps = 5;
  int frames = 400;
  double altitude_min_m = 1.6;
  double altitude_max_m = 2.0;
  double pitch_amp_deg = 3;
  double roll_amp_deg = 2;
  double sea_depth_m = 35;  // depth_m = sea_depth_m - altitude_m
};

struct TimedPose {
  double time_s = 0;
  VehiclePose pose;
};

// Exact poses at frame times i / fps. Altitude, pitch and roll are sums of
// slow sinusoids with seed-dependent phases (altitude stays within
// [min, max], |pitch| <= pitch_amp, |roll| <= roll_amp); heading follows the
// path. Stops early (fewer frames) when the path ends.
std::vector<TimedPose> MakeTrajectory(const SurveyPath& path, const TrajectoryOptions& options, uint64_t seed);

struct NavErrorOptions {
  double position_sigma_m = 0;   // white noise on east and north
  double heading_sigma_deg = 0;  // white noise on heading
  double drift_m_per_min = 0;    // position bias growing linearly in a random direction
};

// The poses a navigation system would report: truth plus the errors.
std::vector<TimedPose> AddNavigationErrors(const std::vector<TimedPose>& truth, const NavErrorOptions& errors,
                                           uint64_t seed);

}  // namespace seamap
