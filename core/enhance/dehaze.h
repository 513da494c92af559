#pragma once
// Dark-channel-prior dehazing of suspended-particle haze (seed 004, eqs. 19-25),
// gated by the Laplacian-variance blur detector: only frames whose sharpness is
// below blur_threshold are dehazed. The dark channel uses the blue and green
// channels only (red is absorbed by water); gray frames use their one channel.
//   I = J t + A (1 - t)                         (eq. 20)
//   t = 1 - omega * dark(I / A)                 (eq. 24)
//   J = (I - A) / max(t, t0) + A                (eq. 25)
#include <opencv2/core.hpp>

namespace seamap {

struct DehazeParams {
  int window = 15;                   // dark-channel patch side (pixels)
  double omega = 0.95;               // haze kept: t = 1 - omega * dark
  double t0 = 0.1;                   // transmission floor
  double airlight_fraction = 0.001;  // brightest dark-channel share used for A
  bool gate = true;                  // dehaze only blurred/hazy frames
  double blur_threshold = 20.0;      // Laplacian variance (8-bit units) below which a frame is hazy
  int blur_levels = 1;               // pyramid levels down before measuring (see blur_metric.h)
  int guided_radius = 20;            // guided-filter refinement of t; 0 = off
  double guided_eps = 1e-3;
  void Validate() const;  // throws InputError("dehaze.<param>")
};

// Dark channel (eq. 19 over blue-green, or the gray channel) of `image` divided
// per channel by `airlight` (eq. 21), as CV_32F in unit range. image: any
// supported type (pixel_format.h) or a unit-range CV_32FC1/CV_32FC3.
cv::Mat DarkChannel(const cv::Mat& image, int window, const cv::Scalar& airlight = cv::Scalar::all(1.0));

// Airlight A per channel (B,G,R or gray in [0]), in unit range: the mean colour of the
// `fraction` of pixels with the brightest dark channel. image as for DarkChannel.
cv::Scalar EstimateAirlight(const cv::Mat& image, const cv::Mat& dark, double fraction);

// Transmission t (eq. 24, optionally guided-filter refined), CV_32FC1, not yet floored.
// image as for DarkChannel; guide is its luma as unit-range CV_32FC1.
cv::Mat EstimateTransmission(const cv::Mat& image, const cv::Mat& guide, const cv::Scalar& airlight,
                             const DehazeParams& params);

// Dehazes when the gate lets the frame through; *applied (optional) tells which happened.
cv::Mat Dehaze(const cv::Mat& image, const DehazeParams& params, bool* applied = nullptr);

}  // namespace seamap
