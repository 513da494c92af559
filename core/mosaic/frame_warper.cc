#include "core/mosaic/frame_warper.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

constexpr int kLut = 1024;
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

}  // namespace

cv::Mat ToEightBit(const cv::Mat& image, int channels, int sixteen_bit_white) {
  cv::Mat eight;
  if (image.depth() == CV_8U) eight = image;
  else if (image.depth() == CV_16U) image.convertTo(eight, CV_8U, 255.0 / sixteen_bit_white);
  else image.convertTo(eight, CV_8U);
  if (eight.channels() == 2) cv::extractChannel(eight, eight, 0);  // gray + alpha
  const int have = eight.channels();
  if (have == channels) return eight;
  cv::Mat out;
  if (channels == 1) cv::cvtColor(eight, out, have == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  else if (have == 1) cv::cvtColor(eight, out, cv::COLOR_GRAY2BGR);
  else cv::cvtColor(eight, out, cv::COLOR_BGRA2BGR);
  return out;
}

FrameWarper::FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom,
                         int tile_size, int channels, double feather_power)
    : camera_(camera),
      frame_(frame),
      zoom_(zoom),
      tile_size_(tile_size),
      channels_(channels),
      feather_power_(feather_power) {
  border_ = camera.HasDistortion() ? camera.Undistort(RawBorder(camera)) : RawBorder(camera);
  weight_lut_.resize(kLut);
  for (int i = 0; i < kLut; ++i)
    weight_lut_[i] = static_cast<float>(std::pow(static_cast<double>(i) / (kLut - 1), feather_power));
}

std::optional<std::array<LocalXY, 4>> FrameWarper::GroundCorners(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;
  std::array<LocalXY, 4> out;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    out[i] = {g.x() / g.z(), g.y() / g.z()};
  }
  return out;
}

std::optional<std::array<LatLon, 4>> FrameWarper::Footprint(const VehiclePose& pose) const {
  auto corners = GroundCorners(pose);
  if (!corners) return std::nullopt;
  std::array<LatLon, 4> out;
  for (int i = 0; i < 4; ++i) out[i] = frame_.ToLatLon((*corners)[i]);
  return out;
}

std::optional<WarpedFrame> FrameWarper::Warp(const cv::Mat& image, const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;

  // Border samples on the map, in global pixel-index coordinates (a pixel's
  // centre is its index; global pixel i spans [i, i+1)).
  std::vector<cv::Point2d> global(border_.size());
  for (size_t i = 0; i < border_.size(); ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    GlobalPixel px = LatLonToPixel(frame_.ToLatLon({g.x() / g.z(), g.y() / g.z()}), zoom_, tile_size_);
    global[i] = {px.x - 0.5, px.y - 0.5};
  }
  WarpedFrame out;
  for (int i = 0; i < 4; ++i)
    out.footprint[i] = PixelToLatLon({global[i].x + 0.5, global[i].y + 0.5}, zoom_, tile_size_);
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : global) {
    min_x = std::min(min_x, p.x); max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y); max_y = std::max(max_y, p.y);
  }
  out.x0 = static_cast<int64_t>(std::floor(min_x));
  out.y0 = static_cast<int64_t>(std::floor(min_y));
  const int width = static_cast<int>(std::ceil(max_x) - out.x0) + 1;
  const int height = static_cast<int>(std::ceil(max_y) - out.y0) + 1;

  // Map pixels -> undistorted image pixels, from the four corners (the
  // seabed-to-Web-Mercator step is affine to far below a pixel over a frame).
  std::vector<cv::Point2f> src(4), dst(4);
  for (int i = 0; i < 4; ++i) {
    src[i] = cv::Point2f(static_cast<float>(border_[i].x), static_cast<float>(border_[i].y));
    dst[i] = cv::Point2f(static_cast<float>(global[i].x - out.x0), static_cast<float>(global[i].y - out.y0));
  }
  cv::Matx33d to_image(cv::getPerspectiveTransform(dst, src));
  // Fold K^-1 in: map pixel -> normalised camera coordinates.
  const cv::Matx33d k_inv = camera_.K().inv();
  const cv::Matx33d m = k_inv * to_image;

  // Per row, one vectorised float pass computes where each pixel samples the
  // raw image (inverse homography + lens distortion) as OpenCV's fixed-point
  // remap tables (integer pixel + 5-bit fractions, what cv::convertMaps
  // makes) and the tent weight there; one cv::remap then samples the frame.
  // This replaces undistort + warpPerspective (two resamplings) and a
  // warped weight image.
  cv::Mat map_xy(height, width, CV_16SC2), map_frac(height, width, CV_16UC1);
  out.weight.create(height, width, CV_8U);
  std::vector<float> tents(width);
  for (int y = 0; y < height; ++y) {
    RowMapping(m, y, width, map_xy.ptr<int16_t>(y), map_frac.ptr<uint16_t>(y), tents.data());
    uint8_t* __restrict w = out.weight.ptr<uint8_t>(y);
    float* __restrict t = tents.data();
    if (feather_power_ != 1.0)
      for (int x = 0; x < width; ++x)
        if (t[x] >= 0) t[x] = weight_lut_[static_cast<int>(t[x] * (kLut - 1))];
    for (int x = 0; x < width; ++x) {  // vectorised: no branches
      const float v = t[x] < 0 ? 0.0f : 1.5f + 254.0f * t[x];
      w[x] = static_cast<uint8_t>(static_cast<int>(v));
    }
  }
  cv::remap(image, out.pixels, map_xy, map_frac, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

namespace {

struct RowParams {
  float a0, a1, b0, b1, c0, c1;  // the homography for this row: (a0 x + a1) / (c0 x + c1) ...
  float k1, k2, k3, p1, p2, fx, fy, cx, cy;
  float max_u, max_v, inv_hw, inv_hh;
  int max_iu, max_iv;  // fixed-point limits keeping (x0 + 1, y0 + 1) inside the image
};

// The per-pixel loop. kClamp guards the float-to-int conversion for rows
// whose mapping may leave the representable range; without it the loop
// vectorises (GCC will not if-convert the clamp).
template <bool kClamp>
void MapRow(const RowParams& p, int width, int16_t* __restrict xy, uint16_t* __restrict frac,
            float* __restrict tent) {
  constexpr float kFixed = cv::INTER_TAB_SIZE;
  constexpr int kOffset = 8192 * cv::INTER_TAB_SIZE;  // keeps truncation a floor
  constexpr int kMask = cv::INTER_TAB_SIZE - 1;
  for (int x = 0; x < width; ++x) {
    const float fxp = static_cast<float>(x);
    const float inv = 1.0f / (p.c0 * fxp + p.c1);
    const float xn = (p.a0 * fxp + p.a1) * inv, yn = (p.b0 * fxp + p.b1) * inv;
    const float r2 = xn * xn + yn * yn;
    const float radial = 1.0f + r2 * (p.k1 + r2 * (p.k2 + r2 * p.k3));
    const float xd = xn * radial + 2.0f * p.p1 * xn * yn + p.p2 * (r2 + 2.0f * xn * xn);
    const float yd = yn * radial + p.p1 * (r2 + 2.0f * yn * yn) + 2.0f * p.p2 * xn * yn;
    float u = p.fx * xd + p.cx, v = p.fy * yd + p.cy;
    if (kClamp) {
      u = std::isfinite(u) ? std::min(std::max(u, -4000.0f), 4000.0f) : -4000.0f;
      v = std::isfinite(v) ? std::min(std::max(v, -4000.0f), 4000.0f) : -4000.0f;
    }
    int iu = static_cast<int>(u * kFixed + 0.5f + kOffset) - kOffset;
    int iv = static_cast<int>(v * kFixed + 0.5f + kOffset) - kOffset;
    // Keep all four bilinear neighbours inside the image (edge pixels are
    // replicated): cv::remap then stays on its vectorised inner path instead
    // of per-pixel border handling. Outside the frame the weight is 0 anyway.
    iu = iu < 0 ? 0 : iu;
    iu = iu > p.max_iu ? p.max_iu : iu;
    iv = iv < 0 ? 0 : iv;
    iv = iv > p.max_iv ? p.max_iv : iv;
    xy[2 * x] = static_cast<int16_t>(iu >> cv::INTER_BITS);
    xy[2 * x + 1] = static_cast<int16_t>(iv >> cv::INTER_BITS);
    frac[x] = static_cast<uint16_t>((iv & kMask) * cv::INTER_TAB_SIZE + (iu & kMask));
    const float ta = std::min(u + 0.5f, p.max_u - u) * p.inv_hw;
    const float tb = std::min(v + 0.5f, p.max_v - v) * p.inv_hh;
    const float t = std::min(ta * tb, 1.0f);
    tent[x] = ((ta > 0.0f) & (tb > 0.0f)) ? t : -1.0f;
  }
}

}  // namespace

void FrameWarper::RowMapping(const cv::Matx33d& m, int y, int width, int16_t* __restrict xy,
                             uint16_t* __restrict frac, float* __restrict tent) const {
  const auto& d = camera_.distortion;
  RowParams p{static_cast<float>(m(0, 0)), static_cast<float>(m(0, 1) * y + m(0, 2)),
              static_cast<float>(m(1, 0)), static_cast<float>(m(1, 1) * y + m(1, 2)),
              static_cast<float>(m(2, 0)), static_cast<float>(m(2, 1) * y + m(2, 2)),
              static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[4]),
              static_cast<float>(d[2]), static_cast<float>(d[3]),
              static_cast<float>(camera_.fx), static_cast<float>(camera_.fy),
              static_cast<float>(camera_.cx), static_cast<float>(camera_.cy),
              camera_.width - 0.5f, camera_.height - 0.5f,
              2.0f / camera_.width, 2.0f / camera_.height,
              (camera_.width - 1) * cv::INTER_TAB_SIZE - 1, (camera_.height - 1) * cv::INTER_TAB_SIZE - 1};
  // The row's normalised coordinates are a linear fraction of x, so when the
  // denominator keeps its sign they are bounded by their values at the ends;
  // bound the distortion polynomial from there to decide if clamping is needed.
  const double z0 = m(2, 2) + m(2, 1) * y, z1 = z0 + m(2, 0) * (width - 1);
  bool safe = z0 > 1e-9 && z1 > 1e-9;
  if (safe) {
    double r = 0;
    for (double x : {0.0, width - 1.0}) {
      const double z = m(2, 0) * x + m(2, 1) * y + m(2, 2);
      r = std::max(r, std::hypot((m(0, 0) * x + m(0, 1) * y + m(0, 2)) / z,
                                 (m(1, 0) * x + m(1, 1) * y + m(1, 2)) / z));
    }
    const double r2 = r * r;
    const double stretch = r * (1 + std::fabs(d[0]) * r2 + std::fabs(d[1]) * r2 * r2 +
                                std::fabs(d[4]) * r2 * r2 * r2) +
                           3 * (std::fabs(d[2]) + std::fabs(d[3])) * r2;
    safe = stretch * std::max(camera_.fx, camera_.fy) + std::max(camera_.cx, camera_.cy) < 4000;
  }
  if (safe) MapRow<false>(p, width, xy, frac, tent);
  else MapRow<true>(p, width, xy, frac, tent);
}

}  // namespace seamap
