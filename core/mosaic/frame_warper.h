#pragma once
// Places one frame on the map: undistorts it, projects it through the
// seabed-plane homography into Web Mercator global pixels at the base zoom,
// and carries a feather weight (a tent that is highest at the image centre
// and falls to zero at the edges) as an extra channel for blending.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct WarpedFrame {
  int64_t x0 = 0, y0 = 0;          // global pixel of pixels(0,0) at the base zoom
  cv::Mat pixels;                  // CV_8UC2 (gray, weight) or CV_8UC4 (B, G, R, weight)
  std::array<LatLon, 4> footprint; // image corners on the seabed (TL, TR, BR, BL)
};

class FrameWarper {
 public:
  // channels: 1 (gray mosaic) or 3 (colour mosaic).
  FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size,
              int channels, double feather_power);

  // Where the frame's corners land, or nullopt when it does not see the seabed.
  std::optional<std::array<LatLon, 4>> Footprint(const VehiclePose& pose) const;

  // image: CV_8UC1 / CV_8UC3 matching `channels`, of the camera's size.
  // Returns nullopt when the frame does not see the seabed.
  std::optional<WarpedFrame> Warp(const cv::Mat& image, const VehiclePose& pose) const;

  const cv::Mat& weight() const { return weight_; }  // undistorted feather weight, CV_8U

 private:
  CameraModel camera_;
  LocalFrame frame_;
  int zoom_, tile_size_, channels_;
  cv::Mat map1_, map2_;  // raw -> undistorted remap tables (empty without distortion)
  cv::Mat weight_;
};

// Converts any image OpenCV reads (gray/colour/alpha, 8/16 bit) to 8-bit with
// `channels` channels. 16-bit values are scaled by 255/white.
cv::Mat ToEightBit(const cv::Mat& image, int channels, int sixteen_bit_white);

}  // namespace seamap
