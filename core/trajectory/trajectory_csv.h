#pragma once
// trajectory.csv: one estimated pose per frame, in the form `seamap build
// --nav` reads as is. Header (binding, docs/specs section 2.5):
//   image,time_s,lat,lon,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg[,flags]
// x_m = east and y_m = north of the frame's origin; lat/lon (WGS84, 1e-10
// degrees, about 0.01 mm) through the same LocalFrame, so a reader with or
// without the origin gets the same positions. The trailing `flags` column
// (e.g. "nav_only") is written only when some row has flags; the navigation
// reader ignores it with a warning.
#include <optional>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct TrajectoryRow {
  std::string image;             // as in the navigation; may be empty when time_s is set
  std::optional<double> time_s;  // seconds, the navigation's epoch; empty cell when absent
  VehiclePose pose;              // local frame of `frame` below
  std::string flags;             // ';'-separated words, e.g. "nav_only"; may be empty
};

// Throws InputError naming the file (and the row's line) when the file cannot
// be written or a row has neither an image nor a time, or text with a line break.
void WriteTrajectoryCsv(const std::string& path, const std::vector<TrajectoryRow>& rows, const LocalFrame& frame);

}  // namespace seamap
