#pragma once
// The vehicle's height above the seabed where no sounder logged it: the
// georeferenced point cloud (the seabed SLAM mapped) below each georeferenced
// keyframe. `seamap build` needs an altitude per photo to size its footprint.
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct SeabedAltitudeOptions {
  double radius_m = 2;  // horizontal radius of the seabed patch below a keyframe
  int min_points = 5;   // fewer points there: no altitude
};

// For each keyframe (metres east, north, up), its up minus the median up of
// the cloud's points (same frame) within radius_m horizontally; nullopt where
// too few points lie below it or the seabed is not below the keyframe.
std::vector<std::optional<double>> AltitudeFromCloud(const std::vector<Eigen::Vector3d>& keyframes_enu_m,
                                                     const std::vector<Eigen::Vector3d>& cloud_enu_m,
                                                     const SeabedAltitudeOptions& options);

}  // namespace seamap
