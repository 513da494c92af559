#pragma once
// Colour-cast removal by gray-world white balance in linear light: the mean of
// each channel over unclipped pixels is made equal (to their average, so overall
// brightness is kept). Frames are treated as gamma-2.2 encoded; a gain g in
// linear light is a gain g^(1/2.2) on the encoded values. Gray frames pass through.
#include <opencv2/core.hpp>

namespace seamap {

struct ColorBalanceParams {
  bool linear = true;     // average in linear light (false: on the encoded values)
  double max_gain = 4.0;  // cap per channel (a nearly absent red channel is mostly noise)
  double clip = 0.98;     // pixels with any channel above this fraction are ignored
  void Validate() const;  // throws InputError("colorbalance.<param>")
};

// Linear-light gains (B, G, R) that gray-world would apply; (1,1,1) for gray frames.
cv::Vec3d GrayWorldGains(const cv::Mat& image, const ColorBalanceParams& params);

cv::Mat BalanceColor(const cv::Mat& image, const ColorBalanceParams& params);

}  // namespace seamap
