#include "core/mosaic/surface_projection.h"

#include <algorithm>
#include <cmath>

#include "core/camera/frame_projector.h"

namespace seamap {
namespace {

// Box pixels added around the border samples: the relief between two samples
// can push the border out a little.
constexpr int kBoxMarginPx = 4;
// A ray must point at least this much downwards (sine) to meet the seabed, as the flat projection's.
constexpr double kMinDownSine = 1e-3;

// Where a camera ray (ENU direction) meets the seabed: the surface, else
// (a hole on the way, off the grid) the frame's plane.
std::optional<Eigen::Vector3d> SeabedHit(const HeightGridRayCaster& rays, const CameraPlacement& c,
                                         const Eigen::Vector3d& ray) {
  if (!(ray.z() < -kMinDownSine * ray.norm())) return std::nullopt;
  const double to_plane = (c.eye_enu.z() - c.plane_up_m) / -ray.z();  // in units of `ray`
  if (!(to_plane > 0)) return std::nullopt;
  double t = 0;
  if (rays.Cast(c.eye_enu, ray, &t)) return c.eye_enu + t * ray;
  return c.eye_enu + to_plane * ray;
}

Eigen::Vector3d RayOf(const CameraModel& camera, const CameraPlacement& c, const cv::Point2d& ideal_px) {
  const Eigen::Vector3d in_camera((ideal_px.x - camera.cx) / camera.fx, (ideal_px.y - camera.cy) / camera.fy, 1.0);
  return c.camera_from_enu.transpose() * in_camera;
}

}  // namespace

CameraPlacement PlaceCamera(const CameraModel& camera, const VehiclePose& pose) {
  Eigen::Matrix3d enu_from_ned;
  enu_from_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Vector3d offset_ned = NedFromBody(pose) * camera.mount_offset_m;
  CameraPlacement c;
  c.eye_enu = {pose.east_m + offset_ned.y(), pose.north_m + offset_ned.x(), -pose.depth_m - offset_ned.z()};
  c.camera_from_enu = (enu_from_ned * NedFromCamera(camera, pose)).transpose();
  c.plane_up_m = -(pose.depth_m + pose.altitude_m);
  return c;
}

SurfaceMapping::SurfaceMapping(const SeabedProjection& flat, const LineOfSight& surface, const VehiclePose& pose,
                               const SeabedProjection::MapTangent& box_to_map, int64_t x0, int64_t y0)
    : flat_(flat),
      surface_(surface),
      camera_(PlaceCamera(flat.camera(), pose)),
      box_to_map_(box_to_map),
      x0_(x0),
      y0_(y0) {}

bool SurfaceMapping::PointAt(double x, double y, Eigen::Vector3d* east_north_up) const {
  // Box pixel-index coordinates -> global ones (a pixel's centre is its
  // index; the tangent's are its corner's) -> local metres.
  const LocalXY p = box_to_map_.ToLocal({static_cast<double>(x0_) + x + 0.5, static_cast<double>(y0_) + y + 0.5});
  double up = 0;
  const bool known = surface_.Height(p.east, p.north, &up);
  *east_north_up = {p.east, p.north, known ? up : camera_.plane_up_m};
  return known;
}

RawPosition SurfaceMapping::See(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d in_camera = camera_.camera_from_enu * (point - camera_.eye_enu);
  if (!(in_camera.z() > 1e-9)) return {};
  return flat_.FromNormalised(in_camera.x() / in_camera.z(), in_camera.y() / in_camera.z());
}

RawPosition SurfaceMapping::ToRaw(double x, double y) const {
  Eigen::Vector3d point;
  const bool known = PointAt(x, y, &point);
  RawPosition raw = See(point);
  if (!raw.valid) return raw;
  const Eigen::Vector3d ray = point - camera_.eye_enu;
  raw.slant = static_cast<float>(ray.head<2>().squaredNorm() / std::max(ray.z() * ray.z(), 1e-12));
  if (!known) return raw;  // a hole: the plane, seen as the flat projection sees it
  // Only what the frame could paint needs the line-of-sight test (the
  // margin: the grid interpolates between points a few pixels apart).
  const CameraModel& c = flat_.camera();
  constexpr float kMarginPx = 8;
  if (raw.u < -kMarginPx || raw.v < -kMarginPx || raw.u > c.width + kMarginPx || raw.v > c.height + kMarginPx)
    return raw;
  if (!surface_.Clear(point, camera_.eye_enu)) return {};
  return raw;
}

SurfaceProjection::SurfaceProjection(const SeabedProjection& flat, std::shared_ptr<const HeightGrid> surface)
    : flat_(flat), rays_(*surface), sight_(*surface) {}

std::optional<SeabedProjection::MapOutline> SurfaceProjection::Outline(const VehiclePose& pose) const {
  if (!flat_.SeesSeabed(pose)) return std::nullopt;
  const CameraModel& camera = flat_.camera();
  const CameraPlacement c = PlaceCamera(camera, pose);
  const std::vector<cv::Point2d>& border = flat_.border();
  std::vector<Eigen::Vector3d> hits;
  hits.reserve(border.size());
  for (const auto& b : border) {
    auto hit = SeabedHit(rays_, c, RayOf(camera, c, b));
    if (!hit) return std::nullopt;
    hits.push_back(*hit);
  }
  const SeabedProjection::MapTangent tangent = flat_.TangentAt({hits[4].x(), hits[4].y()});
  std::vector<cv::Point2d> global(hits.size());
  for (size_t i = 0; i < hits.size(); ++i)
    global[i] = tangent.ToMap({hits[i].x(), hits[i].y()}) - cv::Point2d(0.5, 0.5);
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : global) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  const auto x0 = static_cast<int64_t>(std::floor(min_x)) - kBoxMarginPx;
  const auto y0 = static_cast<int64_t>(std::floor(min_y)) - kBoxMarginPx;
  const std::array<int64_t, 4> box{x0, y0, static_cast<int64_t>(std::ceil(max_x)) + kBoxMarginPx - x0 + 1,
                                   static_cast<int64_t>(std::ceil(max_y)) + kBoxMarginPx - y0 + 1};
  return SeabedProjection::MapOutline{box, {global[0], global[1], global[2], global[3]}, global[4]};
}

std::vector<std::unique_ptr<BoxMapping>> SurfaceProjection::Mappings(const SeabedProjection::MapOutline& frame,
                                                                     const std::vector<VehiclePose>& views) const {
  std::vector<std::unique_ptr<BoxMapping>> out;
  if (views.empty()) return out;
  // Box pixels <-> local metres: the tangent where the frame's centre lands.
  const SeabedProjection::MapTangent probe = flat_.TangentAt({views[0].east_m, views[0].north_m});
  const SeabedProjection::MapTangent box_to_map = flat_.TangentAt(probe.ToLocal(frame.centre + cv::Point2d(0.5, 0.5)));
  const int64_t x0 = frame.box[0], y0 = frame.box[1];
  for (const VehiclePose& v : views)
    out.push_back(std::make_unique<SurfaceMapping>(flat_, sight_, v, box_to_map, x0, y0));
  return out;
}

}  // namespace seamap
