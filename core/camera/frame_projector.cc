#include "core/camera/frame_projector.h"

#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/geo/rotation.h"

namespace seamap {
namespace {

// A ray must point at least this much downwards (sine of its depression angle,
// ~0.06 deg) to count as hitting the seabed; flatter rays land absurdly far away.
constexpr double kMinDownSine = 1e-3;

// Outer pixel edges of the raw image, TL, TR, BR, BL, undistorted.
std::vector<cv::Point2d> UndistortedCorners(const CameraModel& camera) {
  const double w = camera.width, h = camera.height;
  return camera.Undistort({{-0.5, -0.5}, {w - 0.5, -0.5}, {w - 0.5, h - 0.5}, {-0.5, h - 0.5}});
}

// Maps undistorted pixels (u, v, 1) to ray directions in NED.
Eigen::Matrix3d NedRayFromPixel(const CameraModel& camera, const VehiclePose& pose) {
  Eigen::Matrix3d k;
  k << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1;
  return NedFromCamera(camera, pose) * k.inverse();
}

bool PointsDown(const Eigen::Vector3d& ray) {
  return ray.z() > kMinDownSine * ray.norm();
}

// Camera centre in NED relative to the navigation reference point.
Eigen::Vector3d CameraOffsetNed(const CameraModel& camera, const VehiclePose& pose) {
  return NedFromBody(pose) * camera.mount_offset_m;
}

}  // namespace

Eigen::Matrix3d NedFromBody(const VehiclePose& pose) {
  return NedFromBodyDeg(pose.heading_deg, pose.pitch_deg, pose.roll_deg);
}

Eigen::Matrix3d NedFromCamera(const CameraModel& camera, const VehiclePose& pose) {
  return NedFromBody(pose) * camera.BodyFromCamera();
}

std::optional<Eigen::Matrix3d> GroundFromImage(const CameraModel& camera, const VehiclePose& pose) {
  const Eigen::Vector3d c = CameraOffsetNed(camera, pose);
  const double height = pose.altitude_m - c.z();  // camera above the seabed
  if (!(height > 0)) return std::nullopt;

  const Eigen::Matrix3d ray = NedRayFromPixel(camera, pose);
  for (const auto& p : UndistortedCorners(camera))
    if (!PointsDown(ray * Eigen::Vector3d(p.x, p.y, 1))) return std::nullopt;

  // Ground = c + t q with t = height / q_d. In homogeneous (east, north, 1):
  // (e w, n w, w) = A (q_e, q_n, q_d) with w = q_d.
  Eigen::Matrix3d enu_from_ned_order;
  enu_from_ned_order << 0, 1, 0, 1, 0, 0, 0, 0, 1;
  Eigen::Matrix3d a;
  a << height, 0, pose.east_m + c.y(), 0, height, pose.north_m + c.x(), 0, 0, 1;
  Eigen::Matrix3d h = a * enu_from_ned_order * ray;

  // w at the principal point is the optical axis' down component; make it 1.
  const double w_centre = h.row(2).dot(Eigen::Vector3d(camera.cx, camera.cy, 1));
  if (!(w_centre > 0)) return std::nullopt;
  return Eigen::Matrix3d(h / w_centre);
}

std::optional<LocalXY> PixelToGround(const CameraModel& camera, const VehiclePose& pose, double u, double v) {
  const Eigen::Vector3d c = CameraOffsetNed(camera, pose);
  const double height = pose.altitude_m - c.z();
  if (!(height > 0)) return std::nullopt;
  const cv::Point2d p = camera.Undistort({{u, v}}).front();
  const Eigen::Vector3d q = NedRayFromPixel(camera, pose) * Eigen::Vector3d(p.x, p.y, 1);
  if (!PointsDown(q)) return std::nullopt;
  const double t = height / q.z();
  return LocalXY{pose.east_m + c.y() + t * q.y(), pose.north_m + c.x() + t * q.x()};
}

std::optional<std::array<LocalXY, 4>> Footprint(const CameraModel& camera, const VehiclePose& pose) {
  const auto h = GroundFromImage(camera, pose);
  if (!h) return std::nullopt;
  const auto corners = UndistortedCorners(camera);
  std::array<LocalXY, 4> out;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d g = *h * Eigen::Vector3d(corners[i].x, corners[i].y, 1);
    out[i] = {g.x() / g.z(), g.y() / g.z()};
  }
  return out;
}

double GroundSampleDistance(const CameraModel& camera, double altitude_m) {
  return altitude_m / ((camera.fx + camera.fy) / 2);
}

}  // namespace seamap
