#pragma once
// Brightness-consistency recovery for artificial light (seed 004, eqs. 2-12).
// Model: p = [q w + a (1 - w)] alpha. Per window: mean mu, deviation sigma and
// minimum p_min. The reflected signal is recovered as
//   q = (p - p_min) * sigma_alpha_max / sigma                       (eq. 12)
// with sigma_alpha_max = max over windows of sigma * mu_max / mu   (eq. 7).
// Window mean and deviation come from one integral image (box sums), sampled
// every window/5 pixels and interpolated, so the cost does not grow with the window.
// Colour frames are recovered on luma (YCrCb) so hues are kept.
// Caveat: eq. 9 assumes every window holds a near-black pixel; on bright sand
// that fails and the result shows halos around dark objects (see docs_enhance.md).
#include <opencv2/core.hpp>

namespace seamap {

struct BrightnessParams {
  int window = 20;                 // window side in pixels (the paper's 20 x 20)
  double max_gain = 8.0;           // cap on sigma_alpha_max / sigma (noise in flat, dark areas)
  double noise_floor = 0.01;       // sigma floor, fraction of full scale
  double percentile = 0.99;        // robust "max" for sigma_alpha_max, in (0, 1]
  double min_mean_fraction = 0.1;  // windows darker than this * mu_max do not set sigma_alpha_max
  double strength = 1.0;           // blend: 0 = input, 1 = fully recovered
  void Validate() const;           // throws InputError("brightness.<param>")
};

cv::Mat RecoverBrightness(const cv::Mat& image, const BrightnessParams& params);

}  // namespace seamap
