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

// Conventions: core/geo/rotation.h (aerospace ZYX). A pitch of +10 (bow up)
// puts a nadir camera's centre alt*tan(10 deg) ahead of the vehicle. The
// camera sits at NedFromBody * mount_offset_m from the navigation reference
// point; the seabed is the plane down = altitude_m.

// NedFromBodyDeg (core/geo/rotation.h) of the pose's attitude: body-frame
// vectors (x fwd, y stbd, z down) to (north, east, down).
Eigen::Matrix3d NedFromBody(const VehiclePose& pose);

// Rotation taking camera-frame vectors (OpenCV) to NED: NedFromBody * BodyFromCamera.
Eigen::Matrix3d NedFromCamera(const CameraModel& camera, const VehiclePose& pose);

// H maps homogeneous undistorted pixel (u, v, 1) to (east, north, 1) in local
// metres (absolute, including the vehicle position). Empty when the image
// plane does not see the seabed (the ray of some image corner points less
// than ~0.06 deg below the horizon) or the camera is not above the seabed.
// Scaled so that w = 1 at the principal point; w > 0 for every pixel whose
// ray hits the seabed.
std::optional<Eigen::Matrix3d> GroundFromImage(const CameraModel& camera, const VehiclePose& pose);

// Where the ray of one raw (distorted) pixel hits the seabed; empty when it
// does not (points at or above the horizon, or the camera is below the seabed).
std::optional<LocalXY> PixelToGround(const CameraModel& camera, const VehiclePose& pose, double u, double v);

// The four image corners (raw pixels, undistorted first) on the ground, in
// order top-left, top-right, bottom-right, bottom-left. Corners are the outer
// pixel edges: (-0.5, -0.5) ... (w - 0.5, h - 0.5).
std::optional<std::array<LocalXY, 4>> Footprint(const CameraModel& camera, const VehiclePose& pose);

// Ground sample distance at the image centre, metres per pixel.
double GroundSampleDistance(const CameraModel& camera, double altitude_m);

}  // namespace seamap
