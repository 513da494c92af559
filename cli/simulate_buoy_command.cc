// seamap simulate-buoy: a buoy-GPS survey with exact truth, for seamap georef.
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/sim/buoy_survey.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap simulate-buoy --out DIR [options]
Simulates a vehicle towing a GPS buoy: keyframes.txt (TUM, SLAM frame), buoy.csv, depth.csv, altitude.csv,
cloud.ply (SLAM frame), and the truth: truth.csv, truth.json, cloud_truth.ply.
  --out DIR               output folder (must be empty unless --force)    --force
  --seed N                random seed (default 1)       --origin LAT,LON (default 51.0563,13.6190)
  --gps-seed N            the fixes' noise, dropouts and multipath from seed N: the same survey, other GPS errors
vehicle and tether:
  --pattern P             lawnmower | line | hover | circles | spiral | transect (default lawnmower)
  --lines N               survey lines (default 6)      --line-length M (120)   --line-spacing M (15)
  --turn-radius M         lawnmower/transect turns (0: half the spacing, at most that)
  --meander M             weave M metres either side of the track ... --meander-wavelength M (60) ... this often
  --speed V               m/s (default 0.6)             --depth M (12.5)        --depth-wave M (0)
  --depth-period S (600)  of the depth change           --depth-noise M         noise in depth.csv (0)
  --tether-length M (30)  --tether-sag F (0: the buoy trails at (1 - F) of the straight tether's reach)
  --buoy-model M          tractrix (pulled along the tether) | path (runs the vehicle's path, reach behind)
  --slack-drift V         a slack buoy drifts east, m/s (0)
  --current-east V, --current-north V   a current (m/s) carries the buoy: slack it drifts, taut it trails
                          along the vehicle's motion through the water (0)
  --current-offset M      a steady current holds the buoy M metres east (0; no estimator can see it)
  --wave-height M (0)     --wave-period S (4)           the buoy rides waves (an orbit of half the height)
GPS on the buoy:
  --gps-rate HZ (1)       --gps-sigma M (1.5, white per axis)
  --gps-correlated M (0)  --gps-tau S (60)              --dropouts F (0)        --multipath F (0: fixes thrown ...)
  --multipath-m M (20)    ... this far                  --gps-outages N (0)     --gps-outage S (30) long each
  --clock-offset S (0)    added to the fixes' times
SLAM:
  --keyframe-interval S (0.75)   --slam-noise M (0.02)  --submaps N (1: keyframes_1.txt ... when more)
  --cloud-points N (2000)        --seabed-depth M (20)
)";

}  // namespace

int RunSimulateBuoy(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"force", "help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  BuoySurveyOptions o;
  o.out_dir = args.Require("out");
  o.force = args.Flag("force");
  o.seed = SeedArg(args);
  const int gps_seed = args.GetInt("gps-seed", 0);
  if (gps_seed < 0) throw InputError("", 0, "--gps-seed", "expected a non-negative whole number");
  o.gps_seed = static_cast<uint64_t>(gps_seed);
  if (auto origin = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*origin, "--origin");
    o.origin = {ll.lat, ll.lon};
  }
  o.pattern = args.GetOr("pattern", o.pattern);
  o.lines = args.GetInt("lines", o.lines);
  o.line_length_m = args.GetDouble("line-length", o.line_length_m);
  o.line_spacing_m = args.GetDouble("line-spacing", o.line_spacing_m);
  o.turn_radius_m = args.GetDouble("turn-radius", o.turn_radius_m);
  o.meander_m = args.GetDouble("meander", o.meander_m);
  o.meander_wavelength_m = args.GetDouble("meander-wavelength", o.meander_wavelength_m);
  o.speed_mps = args.GetDouble("speed", o.speed_mps);
  o.depth_m = args.GetDouble("depth", o.depth_m);
  o.depth_wave_m = args.GetDouble("depth-wave", o.depth_wave_m);
  o.depth_period_s = args.GetDouble("depth-period", o.depth_period_s);
  o.depth_noise_m = args.GetDouble("depth-noise", o.depth_noise_m);
  o.tether_length_m = args.GetDouble("tether-length", o.tether_length_m);
  o.slack_drift_mps = args.GetDouble("slack-drift", o.slack_drift_mps);
  o.current_offset_m = args.GetDouble("current-offset", o.current_offset_m);
  o.current_east_mps = args.GetDouble("current-east", o.current_east_mps);
  o.current_north_mps = args.GetDouble("current-north", o.current_north_mps);
  o.buoy_model = args.GetOr("buoy-model", o.buoy_model);
  o.tether_sag = args.GetDouble("tether-sag", o.tether_sag);
  o.wave_height_m = args.GetDouble("wave-height", o.wave_height_m);
  o.wave_period_s = args.GetDouble("wave-period", o.wave_period_s);
  o.multipath_m = args.GetDouble("multipath-m", o.multipath_m);
  o.gps_outages = args.GetInt("gps-outages", o.gps_outages);
  o.gps_outage_s = args.GetDouble("gps-outage", o.gps_outage_s);
  o.gps_rate_hz = args.GetDouble("gps-rate", o.gps_rate_hz);
  o.gps_sigma_m = args.GetDouble("gps-sigma", o.gps_sigma_m);
  o.gps_correlated_m = args.GetDouble("gps-correlated", o.gps_correlated_m);
  o.gps_tau_s = args.GetDouble("gps-tau", o.gps_tau_s);
  o.dropout_fraction = args.GetDouble("dropouts", o.dropout_fraction);
  o.multipath_fraction = args.GetDouble("multipath", o.multipath_fraction);
  o.clock_offset_s = args.GetDouble("clock-offset", o.clock_offset_s);
  o.keyframe_interval_s = args.GetDouble("keyframe-interval", o.keyframe_interval_s);
  o.slam_noise_m = args.GetDouble("slam-noise", o.slam_noise_m);
  o.submaps = args.GetInt("submaps", o.submaps);
  o.cloud_points = args.GetInt("cloud-points", o.cloud_points);
  o.seabed_depth_m = args.GetDouble("seabed-depth", o.seabed_depth_m);
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap simulate-buoy --help");

  const BuoySurveySummary s = SimulateBuoySurvey(o);
  std::printf(
      "simulated %s: %d keyframes in %zu file%s, %d GPS fixes, %.0f s, %.0f m path, tether reach %.2f m -> %s\n",
      o.pattern.c_str(), s.keyframes, s.keyframe_files.size(), s.keyframe_files.size() == 1 ? "" : "s", s.fixes,
      s.duration_s, s.path_length_m, s.reach_m, o.out_dir.c_str());
  return 0;
}

}  // namespace seamap::cli
