#pragma once
// A simulated buoy-GPS survey with exact truth, for `seamap simulate-buoy`:
// a vehicle at depth flies a pattern, a buoy trails on its tether (a tractrix
// while pulled, still while slack), a GPS on the buoy logs noisy fixes, and a
// SLAM system reports the keyframes in its own frame: the truth under a
// random similarity (scale, any rotation, translation) plus noise.
#include <cstdint>
#include <string>
#include <vector>

#include "core/geo/lat_lon.h"

namespace seamap {

struct BuoySurveyOptions {
  std::string out_dir;
  bool force = false;
  uint64_t seed = 1;
  uint64_t gps_seed = 0;  // else 0: the fixes' noise, dropouts and multipath from this seed, the survey from `seed`
  LatLon origin{51.0563, 13.6190};  // Oberwartha reservoir, the paper's lake
  // Vehicle.
  std::string pattern = "lawnmower";  // lawnmower | line | hover | circles | spiral | transect
  int lines = 6;
  double line_length_m = 120;
  double line_spacing_m = 15;        // turns are semicircles of half this radius
  double turn_radius_m = 0;          // lawnmower and transect turns; 0 = half the spacing (at most that)
  double meander_m = 0;              // the vehicle weaves this far either side of its track ...
  double meander_wavelength_m = 60;  // ... once along this much of it: it never flies straight
  double speed_mps = 0.6;
  double depth_m = 12.5;
  double depth_wave_m = 0;      // amplitude of a slow depth change
  double depth_period_s = 600;  // its period
  double depth_noise_m = 0;     // pressure sensor noise in depth.csv
  double tether_length_m = 30;
  std::string buoy_model = "tractrix";  // tractrix: pulled along the tether | path: follows the vehicle's path
  double tether_sag = 0;                // the towed buoy trails at (1 - sag) of the straight tether's reach
  double slack_drift_mps = 0;           // a slack buoy drifts east at this speed
  double current_offset_m = 0;          // a steady current holds the buoy this far east (unobservable)
  double current_east_mps = 0;          // a current carries the buoy: slack it drifts, taut it trails
  double current_north_mps = 0;         // along the vehicle's motion through the water (v - current)
  double wave_height_m = 0;             // the buoy rides waves: an orbit of half this radius ...
  double wave_period_s = 4;             // ... this often, from a random direction
  // GPS on the buoy.
  double gps_rate_hz = 1;
  double gps_sigma_m = 1.5;     // white, per axis
  double gps_correlated_m = 0;  // first-order Gauss-Markov, per axis
  double gps_tau_s = 60;
  double dropout_fraction = 0;
  double multipath_fraction = 0;  // fixes thrown multipath_m in a random direction
  double multipath_m = 20;
  int gps_outages = 0;        // stretches without fixes, at random times ...
  double gps_outage_s = 30;   // ... this long each
  double clock_offset_s = 0;  // added to the fixes' times
  // SLAM.
  double keyframe_interval_s = 0.75;  // mean, +-1/3 jitter, halved in turns
  double slam_noise_m = 0.02;         // per axis, before mapping into SLAM units
  int submaps = 1;                    // resets: each part its own file and similarity
  // Point cloud.
  int cloud_points = 2000;
  double seabed_depth_m = 20;
};

struct BuoySurveySummary {
  int keyframes = 0;
  int fixes = 0;
  double duration_s = 0;
  double path_length_m = 0;
  double reach_m = 0;
  std::vector<std::string> keyframe_files;
};

// Writes keyframes.txt (keyframes_N.txt with submaps > 1), buoy.csv,
// depth.csv, altitude.csv (a sounder above the seabed), truth.csv, truth.json, cloud.ply and cloud_truth.ply to
// out_dir. Throws InputError naming the option for bad settings, or when
// out_dir holds a previous run and force is not set.
BuoySurveySummary SimulateBuoySurvey(const BuoySurveyOptions& options);

}  // namespace seamap
