#include "core/enhance/color_balance.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {
namespace {
constexpr double kGamma = 2.2;

// Mean linear (or encoded) value per channel over unclipped pixels, sampling every 2nd pixel.
template <typename T>
cv::Vec3d ChannelMeans(const cv::Mat& image, const ColorBalanceParams& p) {
  const double full = FullScale(image);
  const T clip = static_cast<T>(p.clip * full);
  std::vector<double> decode(static_cast<size_t>(full) + 1);
  for (size_t v = 0; v < decode.size(); ++v) decode[v] = p.linear ? std::pow(v / full, kGamma) : v / full;
  cv::Vec3d sum(0, 0, 0);
  double count = 0;
  for (int y = 0; y < image.rows; y += 2) {
    const cv::Vec<T, 3>* row = image.ptr<cv::Vec<T, 3>>(y);
    for (int x = 0; x < image.cols; x += 2) {
      const auto& px = row[x];
      if (px[0] > clip || px[1] > clip || px[2] > clip) continue;
      for (int c = 0; c < 3; ++c) sum[c] += decode[px[c]];
      ++count;
    }
  }
  return count > 0 ? sum / count : sum;
}

}  // namespace

void ColorBalanceParams::Validate() const {
  RequireParam(max_gain >= 1.0 && max_gain <= 100.0, "colorbalance.max_gain", "a value in [1, 100]", max_gain);
  RequireParam(clip > 0.0 && clip <= 1.0, "colorbalance.clip", "a value in (0, 1]", clip);
}

cv::Vec3d GrayWorldGains(const cv::Mat& image, const ColorBalanceParams& params) {
  params.Validate();
  RequireSupportedImage(image, "colorbalance");
  if (image.channels() == 1) return {1, 1, 1};
  cv::Vec3d means = image.depth() == CV_8U ? ChannelMeans<uchar>(image, params) : ChannelMeans<ushort>(image, params);
  const double target = (means[0] + means[1] + means[2]) / 3.0;
  cv::Vec3d gains;
  for (int c = 0; c < 3; ++c)
    gains[c] = means[c] > 0 ? std::clamp(target / means[c], 1.0 / params.max_gain, params.max_gain) : params.max_gain;
  return gains;
}

cv::Mat BalanceColor(const cv::Mat& image, const ColorBalanceParams& params) {
  cv::Vec3d gains = GrayWorldGains(image, params);
  if (image.channels() == 1) return image.clone();
  cv::Scalar encoded;
  for (int c = 0; c < 3; ++c) encoded[c] = params.linear ? std::pow(gains[c], 1.0 / kGamma) : gains[c];
  cv::Mat out;
  cv::multiply(image, encoded, out);  // saturating per-channel gain
  return out;
}

}  // namespace seamap
