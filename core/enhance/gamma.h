#pragma once
// Gamma correction as in seed 000: V' = Vmax * (V / Vmax)^gamma.
// gamma < 1 brightens dark frames, gamma > 1 darkens.
#include <opencv2/core.hpp>

namespace seamap {

struct GammaParams {
  double gamma = 0.8;
  void Validate() const;  // throws InputError("gamma.gamma")
};

// Works per channel on any supported image type (see pixel_format.h).
cv::Mat ApplyGamma(const cv::Mat& image, const GammaParams& params);

}  // namespace seamap
