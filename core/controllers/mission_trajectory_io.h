#pragma once
// The mission's trajectory (core/mission/mission_trajectory.h) put to use:
// written as trajectory.csv (`build|replay --trajectory-out`, the form
// `seamap trajectory --out` writes and `seamap build --nav` reads), and as a
// time series in the mission's local frame, for the stages that place
// something at a time with the poses the map was painted with (stereo-locate
// --map).
#include <string>
#include <vector>

#include "core/geo/local_frame.h"
#include "core/georef/tum_trajectory.h"
#include "core/mission/mission_trajectory.h"
#include "core/nav/nav_series.h"
#include "core/tiles/tile_store.h"
#include "core/trajectory/trajectory_csv.h"

namespace seamap {

// One row per recorded frame, local positions about `frame`'s origin. A
// corrected mission's frame that kept the navigation's pose (refine found
// no pair for it) is flagged "nav_only".
std::vector<TrajectoryRow> MissionTrajectoryRows(const MissionTrajectory& trajectory, TrajectorySource source,
                                                 const LocalFrame& frame);

// Writes the trajectory the frames were placed with to `path`
// (`option` names it in errors); returns the rows written.
size_t WriteMissionTrajectory(const TileStore& store, const std::string& path, const std::string& option);

// The placed trajectory as a time series about `frame`'s origin: InputError
// naming the map (`map_path`) when it has no frame with a time.
NavSeries MissionTrajectorySeries(const MissionTrajectory& trajectory, const LocalFrame& frame,
                                  const std::string& map_path);

// A pose in `frame`'s local metres as a SLAM-style keyframe: the local frame
// (east, north, up = -depth) as the SLAM frame, the down-looking camera
// (image top to the bow) as its camera; `line` names it in messages.
Keyframe PoseKeyframe(double time_s, const VehiclePose& pose, int line);

// The placed trajectory as SLAM-style keyframes for buoy georeferencing: the
// local frame about the mission's origin (east, north, up = -depth) is the
// "SLAM" frame, the frame's down-looking camera (image top to the bow) its
// camera, in time order (one pose per time). InputError naming the map when
// it has no origin or fewer than two timed frames.
std::vector<Keyframe> MissionKeyframes(const TileStore& store, const std::string& map_path);

}  // namespace seamap
