#pragma once
// The rotations between the vehicle's frames, written once.
//
// Frames:
//  - NED: x north, y east, z down (the local frame's axes, rows of NedFromBody).
//  - body: x forward (bow), y starboard, z down.
//  - camera (OpenCV): x image right, y image down, z along the optical axis.
//
// Convention (aerospace ZYX, intrinsic yaw-pitch-roll):
//   NedFromBody = Rz(heading) * Ry(pitch) * Rx(roll).
// Heading 90 points the bow east; pitch +10 (bow up) tilts the body's down
// axis forward; roll +10 (starboard down) tilts it to port.
#include <Eigen/Core>

namespace seamap {

// Rz(z_rad) * Ry(y_rad) * Rx(x_rad), radians, right-handed.
Eigen::Matrix3d RotationZyx(double z_rad, double y_rad, double x_rad);

// Body-frame vectors to NED for a vehicle with this attitude, degrees.
Eigen::Matrix3d NedFromBodyDeg(double heading_deg, double pitch_deg, double roll_deg);

// How a camera sits on the vehicle before any extra mounting rotation:
//  - kDown: optical axis straight down, image top towards the bow (camera
//    x -> body +y, y -> body -x, z -> body +z);
//  - kForward: optical axis along the bow, image top up (camera x -> body
//    +y, y -> body +z, z -> body +x).
enum class CameraLooking { kDown, kForward };

// Camera-frame vectors to the body frame: R_mount * R_looking, where
// R_mount = RotationZyx(yaw, pitch, roll) of `mount_rpy_deg` = (roll, pitch,
// yaw) in degrees about the body axes (pitch +10 tilts a downward optical
// axis forward, roll +10 towards port, yaw +90 turns image right aft).
// With no mounting rotation the result is exactly R_looking.
Eigen::Matrix3d BodyFromCamera(CameraLooking looking, const Eigen::Vector3d& mount_rpy_deg = Eigen::Vector3d::Zero());

}  // namespace seamap
