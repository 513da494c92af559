#pragma once
// A trajectory against ground truth (docs: visual-odometry-ekf.md, section 4):
// absolute errors with no alignment (both tracks are in the same local frame),
// the seed paper's drift measure, the error between neighbouring passes that
// shows as seams in a mosaic, and the paper's Table 2 body-velocity errors.
//
// Frames are paired by image name when both tracks have names in common,
// else by time (see track_pairing.h). Errors are horizontal (east/north)
// except the velocity's w, which comes from depth.
#include <array>
#include <string>

#include "core/nav/nav_table.h"
#include "core/trajectory/survey_lines.h"

namespace seamap {

// Of the errors estimate - truth on one axis over the frames. RMSE^2 = mean^2 + std^2
// (population std), which the paper's Table 2 does not satisfy.
struct AxisStats {
  double rmse = 0, mean = 0, std = 0;
};

struct TrajectoryErrors {
  int frames = 0;         // paired frames
  std::string paired_by;  // "image" or "time"
  double ate_m = 0;       // RMS of the horizontal error, no alignment
  double rmse_north_m = 0, rmse_east_m = 0;
  double max_error_m = 0;                  // the paper's "MAE" (a maximum) for distance
  double max_north_m = 0, max_east_m = 0;  // largest |error| on each axis
  double path_length_m = 0;                // truth, along the paired frames in time order
  double drift_percent = 0;                // max_error_m / path_length_m * 100; NaN for a zero path
  double end_error_m = 0;                  // horizontal error at the last paired frame
  int lines = 0;                           // survey lines found in the truth (survey_lines.h)
  int cross_pairs = 0;                     // frame pairs on different lines, true centres < 1 m apart
  // |(p_i - p_j) - (ptrue_i - ptrue_j)| over those pairs, millimetres; NaN when there are none.
  // Percentiles interpolate linearly between order statistics (numpy's default).
  double cross_median_mm = 0, cross_p90_mm = 0, cross_max_mm = 0;
  // Body-frame velocity errors (u surge, v sway, w heave) in m/s: central
  // differences of each track's positions (east, north, depth) over the truth's
  // time_s, both rotated into the body frame with the truth attitude
  // (R_nb = Rz(heading) Ry(pitch) Rx(roll)). Interior frames with a time on
  // both neighbours; NaN when there are none.
  std::array<AxisStats, 3> velocity{};
  int velocity_frames = 0;
};

struct EvalOptions {
  LineOptions lines;
  double max_pair_distance_m = 1.0;  // cross-pass pairs: true centres closer than this
};

// Throws InputError naming the estimate's file when no frame pairs with the truth.
TrajectoryErrors EvaluateTrajectory(const NavTable& estimate, const NavTable& truth, const EvalOptions& options = {});

}  // namespace seamap
