#pragma once
// The settings of a buoy georeferencing run. Defaults are the values tuned on
// simulated surveys (docs/GEOREF.md).
#include "core/georef/slam_path.h"

namespace seamap {

enum class GeorefMethod {
  kTether,    // similarity, reach and the buoy's way of following fitted jointly to every fix (default)
  kUmeyama,   // weighted similarity over every good keyframe, outliers rejected
  kTriangle,  // the paper: the largest triangle of good keyframes, rigid SVD (with scale)
};

struct GeorefOptions {
  double tether_length_m = 0;
  GeorefMethod method = GeorefMethod::kTether;
  SlamPath::Options path;
  int min_good_keyframes = 10;
  double max_fix_gap_s = 3;              // a keyframe needs a fix this close on each side
  double min_straightness = 0.98;        // SLAM chord / arc over the last max(t_c, 10 s)
  double max_speed_variation = 0.25;     // of the SLAM keyframe speeds over the same time
  double min_buoy_speed_mps = 0.1;       // and half the leg's median
  double max_dropped_fraction = 0.2;     // of a window's fixes beyond 3.5 sigma of its fit
  double min_direction_sigma_deg = 0.2;  // floor of the buoy direction's error
  double speed_tolerance = 0.2;          // buoy speed against the tether model, of the vehicle's speed
  double min_eigen_ratio = 0.05;         // sqrt(l2 / l1) of the good SLAM positions
  double spot_sigmas = 3;                // the good targets' spread must exceed this many GPS sigmas
  double outlier_sigmas = 3;
  double depth_sigma_m = 0.05;  // vertical sigma of a target (pressure depth), at least
  int max_rounds = 5;           // fit, then targets from the tether model, until the good set holds
  // --method tether, where the geometry cannot see the buoy's offset along
  // the track: how well the fixes' clock agrees with the keyframes', and
  // how much the tether may sag, as a share of its reach (towed_fit.h).
  double clock_sigma_s = 1;
  double sag_sigma = 0.02;
};

}  // namespace seamap
