#include "core/sim/frame_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"

namespace seamap {
namespace {

// Where camera rays (normalised x, y, 1) meet the seabed plane.
struct RayCaster {
  Eigen::Matrix3d rotation;  // camera -> NED
  Eigen::Vector3d centre;    // camera: local north, east; down below the nav point
  double height = 0;         // camera above the seabed

  RayCaster(const CameraModel& camera, const VehiclePose& pose) {
    const Eigen::Matrix3d ned_from_body = NedFromBody(pose);
    rotation = ned_from_body * camera.BodyFromCamera();
    const Eigen::Vector3d offset = ned_from_body * camera.mount_offset_m;
    centre = {pose.north_m + offset.x(), pose.east_m + offset.y(), offset.z()};
    height = pose.altitude_m - offset.z();
  }

  // False when the ray does not go down to the seabed.
  bool Hit(double x, double y, double* east, double* north, double* range) const {
    const Eigen::Vector3d d = rotation.col(0) * x + rotation.col(1) * y + rotation.col(2);
    if (height <= 0 || d.z() < 1e-6) return false;
    const double t = height / d.z();
    *north = centre.x() + t * d.x();
    *east = centre.y() + t * d.y();
    *range = t * d.norm();
    return true;
  }
};

// Camera rays (normalised x, y, 1) cast onto a height model.
struct TerrainRays {
  Eigen::Matrix3d enu_from_camera;
  Eigen::Vector3d centre_enu;  // camera centre: local east, north, up

  TerrainRays(const CameraModel& camera, const VehiclePose& pose) {
    const Eigen::Matrix3d ned_from_body = NedFromBody(pose);
    Eigen::Matrix3d enu_from_ned;
    enu_from_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
    enu_from_camera = enu_from_ned * ned_from_body * camera.BodyFromCamera();
    const Eigen::Vector3d offset = enu_from_ned * ned_from_body * camera.mount_offset_m;
    centre_enu = Eigen::Vector3d(pose.east_m, pose.north_m, -pose.depth_m) + offset;
  }

  bool Hit(const HeightGridRayCaster& terrain, double x, double y, double* east, double* north, double* range) const {
    const Eigen::Vector3d d = enu_from_camera.col(0) * x + enu_from_camera.col(1) * y + enu_from_camera.col(2);
    double t = 0;
    if (!terrain.Cast(centre_enu, d, &t)) return false;
    *east = centre_enu.x() + t * d.x();
    *north = centre_enu.y() + t * d.y();
    *range = t * d.norm();
    return true;
  }
};

constexpr float kMiss = -1e6f;  // remap coordinate far outside any texture

// cv::remap as Render needs it, on textures of any size: cv::remap takes a
// source under 32,767 px a side (a 20,000-frame survey's texture is longer),
// so a larger one is cut to the maps' reach plus the interpolation's
// neighbours and the maps moved by the same whole pixels. The samples are
// bit for bit those of the whole texture (a whole-pixel shift of a float
// coordinate is exact), and a texture under the limit is remapped as before.
void RemapTexture(const cv::Mat& texture, const cv::Mat1f& map_x, const cv::Mat1f& map_y, cv::Mat* frame) {
  constexpr int kRemapLimitPx = 32767;
  if (texture.cols < kRemapLimitPx && texture.rows < kRemapLimitPx) {
    cv::remap(texture, *frame, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
    return;
  }
  double x_min = HUGE_VAL, x_max = -HUGE_VAL, y_min = HUGE_VAL, y_max = -HUGE_VAL;
  for (int v = 0; v < map_x.rows; ++v)
    for (int u = 0; u < map_x.cols; ++u) {
      const float x = map_x(v, u), y = map_y(v, u);
      if (x <= kMiss / 2 || y <= kMiss / 2 || !std::isfinite(x) || !std::isfinite(y)) continue;
      x_min = std::min<double>(x_min, x), x_max = std::max<double>(x_max, x);
      y_min = std::min<double>(y_min, y), y_max = std::max<double>(y_max, y);
    }
  const cv::Rect whole(0, 0, texture.cols, texture.rows);
  cv::Rect reach;
  if (x_min <= x_max && y_min <= y_max) {
    const double x0 = std::max(-1.0, std::floor(x_min) - 2), y0 = std::max(-1.0, std::floor(y_min) - 2);
    const double x1 = std::min<double>(texture.cols, std::ceil(x_max) + 3);
    const double y1 = std::min<double>(texture.rows, std::ceil(y_max) + 3);
    if (x0 < x1 && y0 < y1) {
      reach = cv::Rect(cv::Point(static_cast<int>(x0), static_cast<int>(y0)),
                       cv::Point(static_cast<int>(x1), static_cast<int>(y1))) &
              whole;
    }
  }
  if (reach.empty() || reach.width >= kRemapLimitPx || reach.height >= kRemapLimitPx) {
    if (reach.empty()) {  // nothing of the texture in view: the border's black
      *frame = cv::Mat(map_x.size(), texture.type(), cv::Scalar::all(0));
      return;
    }
    throw std::runtime_error("a frame's view spans more than 32,767 texture pixels");
  }
  cv::Mat1f shifted_x = map_x - static_cast<float>(reach.x), shifted_y = map_y - static_cast<float>(reach.y);
  cv::remap(texture(reach), *frame, shifted_x, shifted_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
}

}  // namespace

FrameRenderer::FrameRenderer(const CameraModel& camera, const Degradations& degradations)
    : camera_(camera), degradations_(degradations) {
  if (degradations.noise_sigma > 0) {
    noise_pool_.create(1, 4 * camera.width * camera.height * 3 + 1024);
    cv::RNG(0x6e6f697365).fill(noise_pool_, cv::RNG::NORMAL, 0, degradations.noise_sigma);
  }
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<size_t>(camera.width) * camera.height);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) pixels.emplace_back(u, v);
  std::vector<cv::Point2d> normalised;
  // No P matrix: the output is the normalised ray (x, y) with z = 1.
  cv::undistortPoints(pixels, normalised, camera.K(), camera.DistortionCoeffs(), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  rays_.create(camera.height, camera.width);
  ray_norm_.create(camera.height, camera.width);
  gain_gray_.create(camera.height, camera.width);
  gain_bgr_.create(camera.height, camera.width);
  // Water absorbs red strongly, blue a little.
  const float cast_b = static_cast<float>(1 - 0.10 * degradations.color_cast);
  const float cast_g = static_cast<float>(1 - 0.02 * degradations.color_cast);
  const float cast_r = static_cast<float>(1 - 0.65 * degradations.color_cast);
  const double half_diagonal = std::hypot(camera.width, camera.height) / 2;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const cv::Point2d& r = normalised[static_cast<size_t>(v) * camera.width + u];
      rays_(v, u) = cv::Vec2f(static_cast<float>(r.x), static_cast<float>(r.y));
      // Lamp: cos^4 off-axis falloff times a soft spot centred on the image.
      const double cos2 = 1 / (1 + r.x * r.x + r.y * r.y);
      ray_norm_(v, u) = static_cast<float>(std::sqrt(1 / cos2));
      const double rho = std::hypot(u - camera.cx, v - camera.cy) / half_diagonal;
      const double light = cos2 * cos2 * std::exp(-rho * rho);
      const float gain = static_cast<float>(1 - degradations.vignetting * (1 - light));
      gain_gray_(v, u) = gain;
      gain_bgr_(v, u) = cv::Vec3f(gain * cast_b, gain * cast_g, gain * cast_r);
    }
}

void FrameRenderer::SetTerrain(const HeightGrid& terrain) {
  terrain_ = std::make_shared<const HeightGridRayCaster>(terrain);
}

bool FrameRenderer::GroundBounds(const VehiclePose& pose, cv::Rect2d* bounds) const {
  const RayCaster caster(camera_, pose);
  const TerrainRays terrain_rays(camera_, pose);
  double e_min = INFINITY, e_max = -INFINITY, n_min = INFINITY, n_max = -INFINITY;
  const auto visit = [&](int u, int v) {
    const cv::Vec2f r = rays_(v, u);
    double east, north, range;
    if (terrain_ ? !terrain_rays.Hit(*terrain_, r[0], r[1], &east, &north, &range)
                 : !caster.Hit(r[0], r[1], &east, &north, &range))
      return false;
    e_min = std::min(e_min, east), e_max = std::max(e_max, east);
    n_min = std::min(n_min, north), n_max = std::max(n_max, north);
    return true;
  };
  const int w = camera_.width, h = camera_.height;
  for (int u = 0; u < w; ++u)
    if (!visit(u, 0) || !visit(u, h - 1)) return false;
  for (int v = 0; v < h; ++v)
    if (!visit(0, v) || !visit(w - 1, v)) return false;
  *bounds = cv::Rect2d(e_min, n_min, e_max - e_min, n_max - n_min);
  return true;
}

void FrameRenderer::TerrainMaps(const SeabedTexture& texture, const VehiclePose& pose, cv::Mat1f* map_x,
                                cv::Mat1f* map_y, cv::Mat1f* range) const {
  const TerrainRays caster(camera_, pose);
  map_x->create(rays_.size());
  map_y->create(rays_.size());
  if (degradations_.haze > 0) range->create(rays_.size());
  cv::parallel_for_(cv::Range(0, rays_.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const cv::Vec2f* ray = rays_[v];
      float* mx = (*map_x)[v];
      float* my = (*map_y)[v];
      for (int u = 0; u < rays_.cols; ++u) {
        double east = 0, north = 0, hit_range = 0;
        const bool hit = caster.Hit(*terrain_, ray[u][0], ray[u][1], &east, &north, &hit_range);
        mx[u] = hit ? static_cast<float>(texture.Column(east)) : kMiss;
        my[u] = hit ? static_cast<float>(texture.Row(north)) : kMiss;
        if (!range->empty()) (*range)(v, u) = hit ? static_cast<float>(hit_range) : 1e3f;
      }
    }
  });
}

void FrameRenderer::PlaneMaps(const SeabedTexture& texture, const VehiclePose& pose, cv::Mat1f* map_x_out,
                              cv::Mat1f* map_y_out, cv::Mat1f* range_out) const {
  const RayCaster caster(camera_, pose);
  // Texture coordinates are a homography of the ray (x, y, 1): with d = R (x, y, 1),
  // column = (e0 - east_min) / res - 0.5 + (h / res) d_east / d_down, and likewise the row.
  const Eigen::Matrix3d& r = caster.rotation;
  const double scale = caster.height / texture.res_m;
  const double col0 = texture.Column(caster.centre.y()), row0 = texture.Row(caster.centre.x());
  const Eigen::RowVector3d num_x = col0 * r.row(2) + scale * r.row(1);
  const Eigen::RowVector3d num_y = row0 * r.row(2) - scale * r.row(0);
  const Eigen::RowVector3d den = r.row(2);
  cv::Mat1f& map_x = *map_x_out;
  cv::Mat1f& map_y = *map_y_out;
  cv::Mat1f& range = *range_out;
  map_x.create(rays_.size());
  map_y.create(rays_.size());
  if (degradations_.haze > 0) range.create(rays_.size());
  cv::parallel_for_(cv::Range(0, rays_.rows), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const cv::Vec2f* ray = rays_[v];
      float* mx = map_x[v];
      float* my = map_y[v];
      for (int u = 0; u < rays_.cols; ++u) {
        const double x = ray[u][0], y = ray[u][1];
        const double w = den[0] * x + den[1] * y + den[2];  // d_down
        const bool hit = caster.height > 0 && w > 1e-6;
        const double inv_w = hit ? 1 / w : 0;
        mx[u] = hit ? static_cast<float>((num_x[0] * x + num_x[1] * y + num_x[2]) * inv_w) : kMiss;
        my[u] = hit ? static_cast<float>((num_y[0] * x + num_y[1] * y + num_y[2]) * inv_w) : kMiss;
        // |d| = |(x, y, 1)|; a ray that misses sees only water.
        if (!range.empty()) range(v, u) = hit ? static_cast<float>(caster.height * ray_norm_(v, u) * inv_w) : 1e3f;
      }
    }
  });
}

cv::Mat FrameRenderer::Render(const SeabedTexture& texture, const VehiclePose& pose, uint64_t noise_seed) const {
  const Degradations& deg = degradations_;
  cv::Mat1f map_x, map_y, range;
  if (terrain_)
    TerrainMaps(texture, pose, &map_x, &map_y, &range);
  else
    PlaneMaps(texture, pose, &map_x, &map_y, &range);
  cv::Mat frame;
  RemapTexture(texture.image, map_x, map_y, &frame);
  if (!deg.Any()) return frame;

  // Degradations, in float and 8-bit units whatever the depth, with
  // vectorised whole-image operations.
  const int channels = frame.channels();
  const double unit = frame.depth() == CV_16U ? 257.0 : 1.0;
  cv::Mat work;
  frame.convertTo(work, CV_MAKETYPE(CV_32F, channels), 1 / unit);
  if (deg.vignetting > 0 || (deg.color_cast > 0 && channels == 3))
    cv::multiply(work, channels == 3 ? cv::Mat(gain_bgr_) : cv::Mat(gain_gray_), work);
  if (!range.empty()) {
    cv::Mat1f t;  // transmission exp(-0.4 haze range)
    cv::exp(range * (-0.4 * deg.haze), t);
    cv::Mat t_n = t;
    if (channels == 3) cv::merge(std::vector<cv::Mat>{t, t, t}, t_n);
    // I = J t + A (1 - t) = (J - A) t + A, with bluish-green (or mid gray) veiling light A.
    const cv::Scalar veil = channels == 3 ? cv::Scalar(140, 115, 45) : cv::Scalar(100);
    cv::subtract(work, veil, work);
    cv::multiply(work, t_n, work);
    cv::add(work, veil, work);
  }
  if (deg.blur_px > 0) {
    // A line kernel along the rows, the fractional end weighted, before the sensor's noise.
    const int len = static_cast<int>(std::ceil(deg.blur_px));
    cv::Mat1f kernel(1, len | 1, 0.f);
    const double half = deg.blur_px / 2;
    for (int k = 0; k < kernel.cols; ++k) {
      const double d = std::abs(k - kernel.cols / 2);
      kernel(0, k) = static_cast<float>(std::clamp(half + 0.5 - d, 0.0, 1.0));
    }
    kernel /= cv::sum(kernel)[0];
    cv::filter2D(work, work, -1, kernel, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  }
  if (deg.noise_sigma > 0) {
    // A window of the precomputed pool at a seeded offset: as random as fresh
    // gaussian noise for any use here, and much cheaper.
    const int n = static_cast<int>(work.total()) * channels;
    const int offset = cv::RNG(noise_seed).uniform(0, static_cast<int>(noise_pool_.total()) - n);
    work += cv::Mat(work.size(), work.type(), const_cast<float*>(noise_pool_.ptr<float>()) + offset);
  }
  work.convertTo(frame, frame.type(), unit);
  return frame;
}

}  // namespace seamap
