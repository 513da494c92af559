#include "core/mosaic/frame_warper.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

// Tent weight in raw pixel space: 1 at the centre, 0 at the border; 8-bit
// with a floor of 1 so every pixel a frame covers carries some weight.
cv::Mat FeatherWeight(int width, int height, double power) {
  cv::Mat w(height, width, CV_8U);
  for (int v = 0; v < height; ++v) {
    const double wy = std::min(v + 0.5, height - 0.5 - v) / (height / 2.0);
    auto* row = w.ptr<uint8_t>(v);
    for (int u = 0; u < width; ++u) {
      const double wx = std::min(u + 0.5, width - 0.5 - u) / (width / 2.0);
      row[u] = static_cast<uint8_t>(1 + std::lround(254 * std::pow(wx * wy, power)));
    }
  }
  return w;
}

std::array<cv::Point2d, 4> ImageCorners(const CameraModel& c) {
  return {cv::Point2d(-0.5, -0.5), cv::Point2d(c.width - 0.5, -0.5),
          cv::Point2d(c.width - 0.5, c.height - 0.5), cv::Point2d(-0.5, c.height - 0.5)};
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
    : camera_(camera), frame_(frame), zoom_(zoom), tile_size_(tile_size), channels_(channels) {
  cv::Mat raw_weight = FeatherWeight(camera.width, camera.height, feather_power);
  if (camera.HasDistortion()) {
    cv::Mat k(camera.K());
    cv::initUndistortRectifyMap(k, camera.DistortionCoeffs(), cv::Mat(), k,
                                cv::Size(camera.width, camera.height), CV_16SC2, map1_, map2_);
    cv::remap(raw_weight, weight_, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  } else {
    weight_ = raw_weight;
  }
}

std::optional<std::array<LatLon, 4>> FrameWarper::Footprint(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;
  std::array<LatLon, 4> out;
  auto corners = ImageCorners(camera_);
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(corners[i].x, corners[i].y, 1.0);
    out[i] = frame_.ToLatLon({g.x() / g.z(), g.y() / g.z()});
  }
  return out;
}

std::optional<WarpedFrame> FrameWarper::Warp(const cv::Mat& image, const VehiclePose& pose) const {
  auto footprint = Footprint(pose);
  if (!footprint) return std::nullopt;

  // Corner correspondences, in pixel-index coordinates on both sides (a
  // pixel's centre is its index; global pixel i spans [i, i+1)).
  auto corners = ImageCorners(camera_);
  std::array<cv::Point2d, 4> global;
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (int i = 0; i < 4; ++i) {
    GlobalPixel g = LatLonToPixel((*footprint)[i], zoom_, tile_size_);
    global[i] = {g.x - 0.5, g.y - 0.5};
    min_x = std::min(min_x, g.x); max_x = std::max(max_x, g.x);
    min_y = std::min(min_y, g.y); max_y = std::max(max_y, g.y);
  }
  WarpedFrame out;
  out.footprint = *footprint;
  out.x0 = static_cast<int64_t>(std::floor(min_x));
  out.y0 = static_cast<int64_t>(std::floor(min_y));
  const int width = static_cast<int>(std::ceil(max_x) - out.x0);
  const int height = static_cast<int>(std::ceil(max_y) - out.y0);

  cv::Point2f src[4], dst[4];
  for (int i = 0; i < 4; ++i) {
    src[i] = cv::Point2f(static_cast<float>(corners[i].x), static_cast<float>(corners[i].y));
    dst[i] = cv::Point2f(static_cast<float>(global[i].x - out.x0),
                         static_cast<float>(global[i].y - out.y0));
  }
  cv::Mat h = cv::getPerspectiveTransform(src, dst);

  cv::Mat undistorted;
  if (map1_.empty()) undistorted = image;
  else cv::remap(image, undistorted, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  cv::Mat with_weight;
  if (channels_ == 1) {
    cv::Mat planes[] = {undistorted, weight_};
    cv::merge(planes, 2, with_weight);
  } else {
    cv::Mat planes[4];
    cv::split(undistorted, planes);
    planes[3] = weight_;
    cv::merge(planes, 4, with_weight);
  }
  cv::warpPerspective(with_weight, out.pixels, h, cv::Size(width, height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

}  // namespace seamap
