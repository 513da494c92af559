#pragma once
// SLAM keyframes in the TUM trajectory format, one a line:
//   timestamp tx ty tz qx qy qz qw
// space separated, '#' comments and blank lines skipped; camera-to-world
// poses (t is the camera centre in SLAM units, the quaternion scalar last),
// as ORB-SLAM and most SLAM systems write them.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace seamap {

struct Keyframe {
  double time_s = 0;                  // seconds, the buoy's clock
  Eigen::Vector3d position_slam;      // camera centre, SLAM units and axes
  Eigen::Quaterniond world_from_cam;  // normalised
  int line = 0;                       // 1-based line in the file
};

// Throws InputError(path, line, field, ...) for a missing file, a line
// without 8 numbers, a timestamp not above the previous one, or a quaternion
// whose norm is outside 1 +- 0.01; and when the file holds no keyframe.
std::vector<Keyframe> ReadTumTrajectory(const std::string& path);

// Writes the keyframes (timestamps with 9 decimals, positions with 9
// significant digits after the point). Throws InputError when it cannot write.
void WriteTumTrajectory(const std::string& path, const std::vector<Keyframe>& keyframes,
                        const std::string& comment = "");

}  // namespace seamap
