#include "core/mosaic/seabed_projection.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

constexpr int kBorderSamples = 16;  // per image edge, to bound curved (distorted) edges

// Points along the raw image border (pixel-edge convention), corners first.
std::vector<cv::Point2d> RawBorder(const CameraModel& c) {
  const double l = -0.5, t = -0.5, r = c.width - 0.5, b = c.height - 0.5;
  std::vector<cv::Point2d> pts{{l, t}, {r, t}, {r, b}, {l, b}};
  for (int i = 1; i < kBorderSamples; ++i) {
    const double f = static_cast<double>(i) / kBorderSamples;
    pts.push_back({l + f * (r - l), t});
    pts.push_back({r, t + f * (b - t)});
    pts.push_back({l + f * (r - l), b});
    pts.push_back({l, t + f * (b - t)});
  }
  return pts;
}

// The whole-pixel box {x0, y0, width, height} around border points.
std::array<int64_t, 4> BoxAround(const std::vector<cv::Point2d>& global) {
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : global) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  const auto x0 = static_cast<int64_t>(std::floor(min_x)), y0 = static_cast<int64_t>(std::floor(min_y));
  return {x0, y0, static_cast<int64_t>(std::ceil(max_x)) - x0 + 1, static_cast<int64_t>(std::ceil(max_y)) - y0 + 1};
}

}  // namespace

SeabedProjection::SeabedProjection(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size)
    : camera_(camera), frame_(frame), zoom_(zoom), tile_size_(tile_size) {
  world_px_ = std::ldexp(static_cast<double>(tile_size), zoom);
  origin_x_ = LatLonToPixel(frame.origin(), zoom, tile_size).x;
  border_ = camera.HasDistortion() ? camera.Undistort(RawBorder(camera)) : RawBorder(camera);
  border_.insert(border_.begin() + 4, cv::Point2d(camera.cx, camera.cy));  // after the corners: the centre
  // A point 20 % further from the optical axis than any border point is
  // outside the image; past there the lens polynomial is not trusted (it can
  // fold far-away points back into the image).
  for (const auto& p : border_) {
    const double xn = (p.x - camera.cx) / camera.fx, yn = (p.y - camera.cy) / camera.fy;
    max_r2_ = std::max(max_r2_, xn * xn + yn * yn);
  }
  max_r2_ *= 1.44;
}

std::optional<std::array<LocalXY, 4>> SeabedProjection::GroundCorners(const VehiclePose& pose) const {
  auto h = GroundFromImage(camera_, pose);
  if (!h) return std::nullopt;
  std::array<LocalXY, 4> out;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    out[i] = {g.x() / g.z(), g.y() / g.z()};
  }
  return out;
}

std::optional<std::array<LatLon, 4>> SeabedProjection::Footprint(const VehiclePose& pose) const {
  auto corners = GroundCorners(pose);
  if (!corners) return std::nullopt;
  std::array<LatLon, 4> out;
  for (int i = 0; i < 4; ++i) {
    out[i] = frame_.ToLatLon((*corners)[i]);
    // A corner near the horizon may be past where PROJ answers: no footprint
    // rather than a record the map cannot read back.
    if (!std::isfinite(out[i].lat) || !std::isfinite(out[i].lon)) return std::nullopt;
  }
  return out;
}

bool SeabedProjection::SeesSeabed(const Eigen::Matrix3d& ground_from_image) const {
  for (const auto& b : border_)
    if ((ground_from_image * Eigen::Vector3d(b.x, b.y, 1.0)).z() <= 0) return false;
  return true;
}

bool SeabedProjection::SeesSeabed(const VehiclePose& pose) const {
  auto h = GroundFromImage(camera_, pose);
  return h && SeesSeabed(*h);
}

std::optional<std::vector<cv::Point2d>> SeabedProjection::MapBorder(const VehiclePose& pose, size_t count) const {
  auto h = GroundFromImage(camera_, pose);
  if (!h || !SeesSeabed(*h)) return std::nullopt;
  // Seabed metres -> global pixels, through PROJ where the principal point
  // lands and a metre east and north of it, then affine: over a frame the
  // projection departs from its tangent by well under a thousandth of a
  // pixel (tested), and it keeps PROJ to three calls per frame.
  const Eigen::Vector3d centre = *h * Eigen::Vector3d(border_[4].x, border_[4].y, 1.0);
  const LocalXY c{centre.x() / centre.z(), centre.y() / centre.z()};
  const MapTangent t = TangentAt(c);
  // A pixel's centre is its index; global pixel i spans [i, i+1).
  std::vector<cv::Point2d> global(std::min(count, border_.size()));
  for (size_t i = 0; i < global.size(); ++i) {
    const Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    const double de = g.x() / g.z() - c.east, dn = g.y() / g.z() - c.north;
    global[i] = {t.at.x + t.east_px.x * de + t.north_px.x * dn - 0.5,
                 t.at.y + t.east_px.y * de + t.north_px.y * dn - 0.5};
  }
  return global;
}

SeabedProjection::MapTangent SeabedProjection::TangentAt(LocalXY c) const {
  auto to_pixel = [&](double east, double north) {
    return LatLonToPixel(frame_.ToLatLon({east, north}), zoom_, tile_size_);
  };
  GlobalPixel p0 = to_pixel(c.east, c.north), pe = to_pixel(c.east + 1, c.north), pn = to_pixel(c.east, c.north + 1);
  // Longitudes wrap at the antimeridian, the survey does not: global pixels
  // go on past the world's edge, on the side of the mission's origin (so
  // neighbouring frames stay neighbours), and tiles wrap (tile_forecast.h).
  auto unwrap = [this](double x, double near) { return x + world_px_ * std::round((near - x) / world_px_); };
  p0.x = unwrap(p0.x, origin_x_);
  pe.x = unwrap(pe.x, p0.x);
  pn.x = unwrap(pn.x, p0.x);
  return {c, {p0.x, p0.y}, {pe.x - p0.x, pe.y - p0.y}, {pn.x - p0.x, pn.y - p0.y}};
}

LocalXY SeabedProjection::MapTangent::ToLocal(cv::Point2d map) const {
  const cv::Point2d d = map - at;
  const double det = east_px.x * north_px.y - north_px.x * east_px.y;
  return {centre.east + (d.x * north_px.y - north_px.x * d.y) / det,
          centre.north + (east_px.x * d.y - d.x * east_px.y) / det};
}

std::optional<SeabedProjection::MapOutline> SeabedProjection::Outline(const VehiclePose& pose) const {
  auto global = MapBorder(pose);
  if (!global) return std::nullopt;
  const auto& g = *global;
  return MapOutline{BoxAround(g), {g[0], g[1], g[2], g[3]}, g[4]};
}

cv::Matx33d SeabedProjection::CameraFromBox(const MapOutline& frame, int64_t x0, int64_t y0) const {
  // From the four corners: the seabed-to-Web-Mercator step is affine to far
  // below a pixel over a frame. Offsets are taken in double before going to
  // float (global pixels at zoom 25 need 33 bits).
  std::vector<cv::Point2f> src(4), dst(4);
  for (int i = 0; i < 4; ++i) {
    src[i] = cv::Point2f(static_cast<float>(border_[i].x), static_cast<float>(border_[i].y));
    dst[i] = cv::Point2f(static_cast<float>(frame.corners[i].x - x0), static_cast<float>(frame.corners[i].y - y0));
  }
  const cv::Matx33d image_from_box(cv::getPerspectiveTransform(dst, src));
  return camera_.K().inv() * image_from_box;
}

RawPosition SeabedProjection::ToRaw(const cv::Matx33d& m, double x, double y) const {
  const double z = m(2, 0) * x + m(2, 1) * y + m(2, 2);
  if (!(z > 1e-12)) return {};
  return FromNormalised((m(0, 0) * x + m(0, 1) * y + m(0, 2)) / z, (m(1, 0) * x + m(1, 1) * y + m(1, 2)) / z);
}

RawPosition SeabedProjection::FromNormalised(double xn, double yn) const {
  const double r2 = xn * xn + yn * yn;
  if (!(r2 <= max_r2_)) return {};
  const auto& d = camera_.distortion;
  const double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  const double xd = xn * radial + 2 * d[2] * xn * yn + d[3] * (r2 + 2 * xn * xn);
  const double yd = yn * radial + d[2] * (r2 + 2 * yn * yn) + 2 * d[3] * xn * yn;
  return {static_cast<float>(camera_.fx * xd + camera_.cx), static_cast<float>(camera_.fy * yd + camera_.cy), true};
}

}  // namespace seamap
