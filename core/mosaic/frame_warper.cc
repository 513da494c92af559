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
constexpr int kStep = 8;            // coarse grid spacing for the pixel mapping

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

std::optional<std::array<LatLon, 4>> FrameWarper::Footprint(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;
  std::array<LatLon, 4> out;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    out[i] = frame_.ToLatLon({g.x() / g.z(), g.y() / g.z()});
  }
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

  // The exact mapping is evaluated on a coarse grid (one sample per kStep
  // pixels, starting one cell before the box so interpolation never clamps)
  // and interpolated bilinearly by cv::resize: the mapping is smooth, and the
  // interpolation error is far below 0.01 px, at a fraction of the cost.
  const int nx = width / kStep + 3, ny = height / kStep + 3;
  cv::Mat coarse_x(ny, nx, CV_32F), coarse_y(ny, nx, CV_32F);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double px = (i - 1 + 0.5) * kStep - 0.5, py = (j - 1 + 0.5) * kStep - 0.5;
      const cv::Point2d uv = MapToImage(m, px, py);
      coarse_x.at<float>(j, i) = static_cast<float>(uv.x);
      coarse_y.at<float>(j, i) = static_cast<float>(uv.y);
    }
  }
  cv::Mat fine_x, fine_y;
  cv::resize(coarse_x, fine_x, cv::Size(nx * kStep, ny * kStep), 0, 0, cv::INTER_LINEAR);
  cv::resize(coarse_y, fine_y, cv::Size(nx * kStep, ny * kStep), 0, 0, cv::INTER_LINEAR);
  const cv::Rect box(kStep, kStep, width, height);
  cv::Mat map_x = fine_x(box), map_y = fine_y(box);

  // Feather weight from where each map pixel samples the raw image.
  const float max_u = camera_.width - 0.5f, max_v = camera_.height - 0.5f;
  const float inv_hw = 2.0f / camera_.width, inv_hh = 2.0f / camera_.height;
  const bool linear = feather_power_ == 1.0;
  out.weight.create(height, width, CV_8U);
  for (int y = 0; y < height; ++y) {
    const float* mx = map_x.ptr<float>(y);
    const float* my = map_y.ptr<float>(y);
    uint8_t* w = out.weight.ptr<uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      const float a = std::min(mx[x] + 0.5f, max_u - mx[x]) * inv_hw;
      const float b = std::min(my[x] + 0.5f, max_v - my[x]) * inv_hh;
      float t = std::max(a, 0.0f) * std::max(b, 0.0f);
      if (!linear) t = weight_lut_[static_cast<int>(std::min(t, 1.0f) * (kLut - 1))];
      w[x] = (a > 0.0f && b > 0.0f) ? static_cast<uint8_t>(1.5f + 254.0f * std::min(t, 1.0f)) : 0;
    }
  }
  cv::remap(image, out.pixels, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

cv::Point2d FrameWarper::MapToImage(const cv::Matx33d& m, double x, double y) const {
  const double zw = m(2, 0) * x + m(2, 1) * y + m(2, 2);
  double xn = (m(0, 0) * x + m(0, 1) * y + m(0, 2)) / zw;
  double yn = (m(1, 0) * x + m(1, 1) * y + m(1, 2)) / zw;
  if (camera_.HasDistortion()) {
    const auto& d = camera_.distortion;
    const double r2 = xn * xn + yn * yn;
    const double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
    const double xd = xn * radial + 2 * d[2] * xn * yn + d[3] * (r2 + 2 * xn * xn);
    const double yd = yn * radial + d[2] * (r2 + 2 * yn * yn) + 2 * d[3] * xn * yn;
    xn = xd;
    yn = yd;
  }
  return {camera_.fx * xn + camera_.cx, camera_.fy * yn + camera_.cy};
}

}  // namespace seamap
