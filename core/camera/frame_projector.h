#pragma once
// Where a frame lands on the seabed: the plane homography from undistorted
// image pixels to local ground coordinates, for a flat seabed `altitude_m`
// below the navigation reference point, with the full attitude (heading,
// pitch, roll) and the camera mounting.
#include <array>
#include <optional>

#include <Eigen/Core>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"

namespace seamap {

// Rotation taking body-frame vectors (x fwd, y stbd, z down) to the local
// NED-like frame used here: columns are (north, east, down) components.
Eigen::Matrix3d BodyToNed(const VehiclePose& pose);

// H maps homogeneous undistorted pixel (u, v, 1) to (east, north, 1) in local
// metres (absolute, including the vehicle position). Empty when the image
// plane does not see the seabed (some ray points at or above the horizon).
std::optional<Eigen::Matrix3d> ImageToGround(const CameraModel& camera, const VehiclePose& pose);

// The four image corners (raw pixels, undistorted first) on the ground, in
// order top-left, top-right, bottom-right, bottom-left.
std::optional<std::array<LocalXY, 4>> Footprint(const CameraModel& camera,
                                                 const VehiclePose& pose);

// Ground sample distance at the image centre, metres per pixel.
double GroundSampleDistance(const CameraModel& camera, double altitude_m);

}  // namespace seamap
