#pragma once
// Places one frame on the map. For every output pixel (Web Mercator global
// pixels at the base zoom, inside the frame's bounding box) it computes where
// the pixel comes from in the raw image — inverse seabed homography, then the
// lens distortion model — samples the raw frame there with one cv::remap (no
// separate undistortion pass) and computes the feather weight there: a tent
// that is 1 at the image centre and falls to 0 at the raw image edges.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct WarpedFrame {
  int64_t x0 = 0, y0 = 0;           // global pixel of pixels(0,0) at the base zoom
  cv::Mat pixels;                   // CV_8UC1 (gray) or CV_8UC3 (BGR)
  cv::Mat weight;                   // CV_8UC1, 0 outside the frame, 1..255 inside
  std::array<LatLon, 4> footprint;  // raw image corners on the seabed (TL, TR, BR, BL)
};

class FrameWarper {
 public:
  // channels: 1 (gray mosaic) or 3 (colour mosaic).
  FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size,
              int channels, double feather_power);

  // Where the raw image corners land, or nullopt when the frame does not see the seabed.
  std::optional<std::array<LatLon, 4>> Footprint(const VehiclePose& pose) const;
  // The same corners in the local frame (metres east/north).
  std::optional<std::array<LocalXY, 4>> GroundCorners(const VehiclePose& pose) const;

  // image: CV_8UC1 / CV_8UC3 matching `channels`, of the camera's size.
  // Returns nullopt when the frame does not see the seabed.
  std::optional<WarpedFrame> Warp(const cv::Mat& image, const VehiclePose& pose) const;

 private:
  // For map row y (relative to the box): where each pixel samples the raw
  // image, through the inverse homography m (to normalised coordinates) and
  // the lens distortion, as fixed-point remap tables, and the tent weight
  // there (-1 outside the image).
  void RowMapping(const cv::Matx33d& m, int y, int width, int16_t* __restrict xy,
                  uint16_t* __restrict frac, float* __restrict tent) const;

  CameraModel camera_;
  LocalFrame frame_;
  int zoom_, tile_size_, channels_;
  double feather_power_;
  std::vector<cv::Point2d> border_;  // raw image border samples, undistorted
  std::vector<float> weight_lut_;    // tent^power, indexed by tent * (kLut - 1)
};

// Converts any image OpenCV reads (gray/colour/alpha, 8/16 bit) to 8-bit with
// `channels` channels. 16-bit values are scaled by 255/white.
cv::Mat ToEightBit(const cv::Mat& image, int channels, int sixteen_bit_white);

}  // namespace seamap
