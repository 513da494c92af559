#pragma once
// Where a frame's pixels meet the seabed, relative to the vehicle and
// without its heading: the horizontal offset a(p) from the vehicle to the
// seabed point seen at ideal pixel p, with the frame's pitch, roll, camera
// mount and altitude but heading 0 (east, north). With the vehicle at t and
// heading psi the point is G = t + Rot(psi) a(p), Rot(psi) = [[cos, sin],
// [-sin, cos]] on (east, north): clockwise by psi. Registration and the
// pose graph (pose_graph.h) share this convention.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"

namespace seamap {

// Rot(psi) applied to (east, north).
inline cv::Point2d RotateClockwise(const cv::Point2d& v, double psi_rad) {
  const double c = std::cos(psi_rad), s = std::sin(psi_rad);
  return {c * v.x + s * v.y, -s * v.x + c * v.y};
}

// Angle difference wrapped to (-pi, pi].
double WrapAngle(double rad);

// The offsets of `ideal_px` for a frame at `pose` (its position and heading
// are ignored); nullopt when the camera does not see the seabed.
std::optional<std::vector<cv::Point2d>> GroundOffsets(const CameraModel& camera, const VehiclePose& pose,
                                                      const std::vector<cv::Point2f>& ideal_px);

}  // namespace seamap
