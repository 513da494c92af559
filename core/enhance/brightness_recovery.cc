#include "core/enhance/brightness_recovery.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {
namespace {

// Window statistics sampled every `stride` pixels: the windows are much larger
// than the stride, so the maps are smooth and bilinear upsampling loses nothing.
struct WindowGrid {
  int stride;
  cv::Mat mu, sigma;  // CV_32F, one value per grid point (eqs. 3-4)
};

WindowGrid WindowStats(const cv::Mat& luma, int window) {
  WindowGrid g;
  g.stride = std::max(1, window / 5);
  const int gw = (luma.cols + g.stride - 1) / g.stride, gh = (luma.rows + g.stride - 1) / g.stride;
  g.mu.create(gh, gw, CV_32F);
  g.sigma.create(gh, gw, CV_32F);
  cv::Mat sum, sqsum;
  cv::integral(luma, sum, sqsum, CV_64F, CV_64F);
  auto span = [&](int centre, int limit) {
    int lo = std::clamp(centre - window / 2, 0, std::max(0, limit - window));
    return std::make_pair(lo, std::min(limit, lo + window));
  };
  for (int gy = 0; gy < gh; ++gy) {
    auto [y0, y1] = span(gy * g.stride + g.stride / 2, luma.rows);
    for (int gx = 0; gx < gw; ++gx) {
      auto [x0, x1] = span(gx * g.stride + g.stride / 2, luma.cols);
      const double n = double(x1 - x0) * (y1 - y0);
      const double s =
          sum.at<double>(y1, x1) - sum.at<double>(y0, x1) - sum.at<double>(y1, x0) + sum.at<double>(y0, x0);
      const double sq =
          sqsum.at<double>(y1, x1) - sqsum.at<double>(y0, x1) - sqsum.at<double>(y1, x0) + sqsum.at<double>(y0, x0);
      g.mu.at<float>(gy, gx) = static_cast<float>(s / n);
      g.sigma.at<float>(gy, gx) = static_cast<float>(std::sqrt(std::max(0.0, (sq - s * s / n) / std::max(1.0, n - 1))));
    }
  }
  return g;
}

// Robust maximum of sigma * mu_max / mu over the well-lit windows (eq. 7).
double SigmaAlphaMax(const WindowGrid& g, double mu_max, const BrightnessParams& p) {
  const float min_mu = static_cast<float>(std::max(p.min_mean_fraction * mu_max, 1e-6));
  std::vector<float> values;
  values.reserve(g.mu.total());
  for (int y = 0; y < g.mu.rows; ++y)
    for (int x = 0; x < g.mu.cols; ++x) {
      const float m = g.mu.at<float>(y, x);
      if (m >= min_mu) values.push_back(g.sigma.at<float>(y, x) * static_cast<float>(mu_max) / m);
    }
  if (values.empty()) return 0.0;
  size_t k = std::min(values.size() - 1, static_cast<size_t>(p.percentile * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

// Grid map -> full resolution (grid point i sits at pixel i * stride + stride / 2).
cv::Mat Upsample(const cv::Mat& grid, int stride, const cv::Size& size) {
  cv::Mat up;
  cv::resize(grid, up, cv::Size(grid.cols * stride, grid.rows * stride), 0, 0, cv::INTER_LINEAR);
  return up(cv::Rect(0, 0, size.width, size.height));
}

}  // namespace

void BrightnessParams::Validate() const {
  RequireParam(window >= 3 && window <= 255, "brightness.window", "a whole number in [3, 255]", window);
  RequireParam(max_gain >= 1.0 && max_gain <= 100.0, "brightness.max_gain", "a value in [1, 100]", max_gain);
  RequireParam(noise_floor > 0.0 && noise_floor < 1.0, "brightness.noise_floor", "a value in (0, 1)", noise_floor);
  RequireParam(percentile > 0.0 && percentile <= 1.0, "brightness.percentile", "a value in (0, 1]", percentile);
  RequireParam(min_mean_fraction >= 0.0 && min_mean_fraction < 1.0, "brightness.min_mean_fraction", "a value in [0, 1)",
               min_mean_fraction);
  RequireParam(strength >= 0.0 && strength <= 1.0, "brightness.strength", "a value in [0, 1]", strength);
}

namespace {
// Eqs. 3-12 on one unit-range CV_32FC1 channel.
cv::Mat RecoverChannel(const cv::Mat& p, const BrightnessParams& params) {
  const WindowGrid grid = WindowStats(p, params.window);
  double mu_max = 0.0;
  cv::minMaxLoc(grid.mu, nullptr, &mu_max);
  const double sigma_alpha_max = SigmaAlphaMax(grid, mu_max, params);
  if (sigma_alpha_max <= 0.0) return p.clone();  // black frame: nothing to recover

  // Gain sigma_alpha_max / sigma (eq. 12), floored against noise and capped.
  cv::Mat gain;
  cv::max(grid.sigma, params.noise_floor, gain);
  cv::divide(sigma_alpha_max, gain, gain);
  cv::min(gain, params.max_gain, gain);
  gain = Upsample(gain, grid.stride, p.size());

  // Window minimum p_min (eqs. 9-10: the scattered-light floor), averaged onto
  // the grid and interpolated back so it has no block edges.
  cv::Mat p_min;
  cv::erode(p, p_min, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(params.window, params.window)),
            cv::Point(-1, -1), 1, cv::BORDER_REFLECT);
  cv::resize(p_min, p_min, grid.mu.size(), 0, 0, cv::INTER_AREA);
  p_min = Upsample(p_min, grid.stride, p.size());

  cv::Mat q = p - p_min;
  cv::max(q, 0.0, q);
  q = q.mul(gain);
  // q lives in "evenly lit" units; stretch it so mean + 3 std lands at 90% of full scale.
  cv::Scalar mean, dev;
  cv::meanStdDev(q, mean, dev);
  const double top = mean[0] + 3.0 * dev[0];
  if (top > 1e-6) q *= 0.9 / top;
  if (params.strength < 1.0) cv::addWeighted(q, params.strength, p, 1.0 - params.strength, 0.0, q);
  return q;
}
}  // namespace

cv::Mat RecoverBrightness(const cv::Mat& image, const BrightnessParams& params) {
  params.Validate();
  RequireSupportedImage(image, "brightness");
  const cv::Mat unit = ToUnitFloat(image);
  if (unit.channels() == 1) return FromUnitFloat(RecoverChannel(unit, params), image.type());
  // Colour: recover luma only and keep chroma, so the lamp correction does not shift hues.
  cv::Mat ycrcb;
  cv::cvtColor(unit, ycrcb, cv::COLOR_BGR2YCrCb);
  std::vector<cv::Mat> planes;
  cv::split(ycrcb, planes);
  planes[0] = RecoverChannel(planes[0], params);
  cv::merge(planes, ycrcb);
  cv::cvtColor(ycrcb, ycrcb, cv::COLOR_YCrCb2BGR);
  return FromUnitFloat(ycrcb, image.type());
}

}  // namespace seamap
