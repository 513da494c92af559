#pragma once
// SeaMap's own trajectory (visual odometry or refinement: no absolute fixes)
// put on the Earth with the GPS fixes of a buoy towed on a tether: what
// `seamap trajectory --mode vo|refine --buoy` runs. The trajectory plays the
// SLAM keyframes' role in seed 002's method (core/controllers/buoy_georef.h):
// it is metric already, so the fitted scale should come out near 1.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/controllers/buoy_georef.h"
#include "core/geo/local_frame.h"
#include "core/trajectory/trajectory_csv.h"

namespace seamap {

struct TrajectoryGeoref {
  // The rows moved onto the Earth, in the same local frame (the survey's
  // origin re-anchored): positions and headings from the fit, depth,
  // altitude, pitch and roll as estimated. A row whose keyframe the fit did
  // not use gets the flag "buoy_unused" (it is still mapped by the fit).
  std::vector<TrajectoryRow> rows;
  double scale = 1;             // metres per trajectory metre: ~1 for a metric trajectory
  double rotation_deg = 0;      // the fit's turn about the vertical
  double shift_m = 0;           // how far the fit moved the trajectory's start horizontally
  double predicted_rmse_m = 0;  // the fit's expected horizontal error over all rows (2D RMS)
  double residual_rmse_m = 0;   // the good keyframes' horizontal residual to the buoy's targets
  int keyframes = 0, good = 0;
  nlohmann::json report;  // the georef report (as `seamap georef --report` writes it)
};

// `options` carries the buoy, tether, depth and method (as `seamap georef`
// reads them); its keyframes, origin and out are set here. Rows without a time
// cannot be placed against the fixes: InputError naming the first. InputError
// as BuoyGeoref for bad logs and a fit that cannot be made.
TrajectoryGeoref GeoreferenceTrajectory(const std::vector<TrajectoryRow>& rows, const LocalFrame& frame,
                                        BuoyGeorefOptions options);

}  // namespace seamap
