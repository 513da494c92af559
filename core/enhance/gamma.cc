#include "core/enhance/gamma.h"

#include <cmath>
#include <vector>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {

void GammaParams::Validate() const {
  RequireParam(gamma > 0.0 && gamma <= 10.0, "gamma.gamma", "a value in (0, 10]", gamma);
}

cv::Mat ApplyGamma(const cv::Mat& image, const GammaParams& params) {
  params.Validate();
  RequireSupportedImage(image, "gamma");
  const double full = FullScale(image);
  // A lookup table over every code value: exact and cheap for 8 and 16 bit.
  if (image.depth() == CV_8U) {
    cv::Mat lut(1, 256, CV_8U);
    for (int v = 0; v < 256; ++v) lut.at<uchar>(v) = cv::saturate_cast<uchar>(full * std::pow(v / full, params.gamma));
    cv::Mat out;
    cv::LUT(image, lut, out);
    return out;
  }
  std::vector<ushort> lut(65536);
  for (int v = 0; v < 65536; ++v) lut[v] = cv::saturate_cast<ushort>(full * std::pow(v / full, params.gamma));
  cv::Mat out(image.size(), image.type());
  const int row_len = image.cols * image.channels();
  for (int y = 0; y < image.rows; ++y) {
    const ushort* src = image.ptr<ushort>(y);
    ushort* dst = out.ptr<ushort>(y);
    for (int i = 0; i < row_len; ++i) dst[i] = lut[src[i]];
  }
  return out;
}

}  // namespace seamap
