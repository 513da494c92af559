#include "core/geo/rotation.h"

#include <cmath>

#include <Eigen/Geometry>

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

Eigen::Matrix3d RotationZyx(double z_rad, double y_rad, double x_rad) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  return (AngleAxisd(z_rad, Vector3d::UnitZ()) * AngleAxisd(y_rad, Vector3d::UnitY()) *
          AngleAxisd(x_rad, Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d NedFromBodyDeg(double heading_deg, double pitch_deg, double roll_deg) {
  return RotationZyx(heading_deg * kDegToRad, pitch_deg * kDegToRad, roll_deg * kDegToRad);
}

Eigen::Matrix3d BodyFromCamera(CameraLooking looking, const Eigen::Vector3d& mount_rpy_deg) {
  // Columns: camera x, y, z expressed in the body frame.
  Eigen::Matrix3d body_from_camera;
  if (looking == CameraLooking::kForward) {
    body_from_camera << 0, 0, 1,  //
        1, 0, 0,                  //
        0, 1, 0;
  } else {
    body_from_camera << 0, -1, 0,  //
        1, 0, 0,                   //
        0, 0, 1;
  }
  const Eigen::Matrix3d mount =
      RotationZyx(mount_rpy_deg.z() * kDegToRad, mount_rpy_deg.y() * kDegToRad, mount_rpy_deg.x() * kDegToRad);
  return mount * body_from_camera;
}

}  // namespace seamap
