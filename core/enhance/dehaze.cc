#include "core/enhance/dehaze.h"

#include <algorithm>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/enhance/blur_metric.h"
#include "core/enhance/guided_filter.h"
#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {
namespace {

// Window minimum of blue and green (or the gray channel), on the native type.
std::vector<cv::Mat> ErodedBlueGreen(const cv::Mat& image, int window) {
  cv::Mat eroded;
  cv::erode(image, eroded, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(window, window)), cv::Point(-1, -1), 1,
            cv::BORDER_REFLECT);
  std::vector<cv::Mat> planes;
  cv::split(eroded, planes);
  planes.resize(std::min<size_t>(2, planes.size()));  // red is absorbed by water: not used
  return planes;
}

// min over channels of eroded_c / (full * A_c), as unit-range CV_32F.
cv::Mat DarkFromEroded(const std::vector<cv::Mat>& planes, double full, const cv::Scalar& airlight) {
  cv::Mat dark;
  for (size_t c = 0; c < planes.size(); ++c) {
    cv::Mat scaled;
    planes[c].convertTo(scaled, CV_32F, 1.0 / (full * std::max(airlight[c], 1e-3)));
    dark = c == 0 ? scaled : cv::min(dark, scaled);
  }
  return dark;
}

double FullOf(const cv::Mat& image) {
  return image.depth() == CV_32F ? 1.0 : FullScale(image);
}

cv::Mat TransmissionFromDark(const cv::Mat& dark, const cv::Mat& guide, const DehazeParams& params) {
  cv::Mat t = 1.0 - params.omega * dark;
  if (params.guided_radius > 0)  // t is smooth: a quarter-resolution guided filter is enough
    t = GuidedFilter(guide, t, params.guided_radius, params.guided_eps, 4);
  return t;
}

}  // namespace

void DehazeParams::Validate() const {
  RequireParam(window >= 1 && window <= 255, "dehaze.window", "a whole number in [1, 255]", window);
  RequireParam(omega > 0.0 && omega <= 1.0, "dehaze.omega", "a value in (0, 1]", omega);
  RequireParam(t0 > 0.0 && t0 < 1.0, "dehaze.t0", "a value in (0, 1)", t0);
  RequireParam(airlight_fraction > 0.0 && airlight_fraction <= 0.5, "dehaze.airlight_fraction", "a value in (0, 0.5]",
               airlight_fraction);
  RequireParam(blur_threshold >= 0.0, "dehaze.blur_threshold", "a value >= 0", blur_threshold);
  RequireParam(blur_levels >= 0 && blur_levels <= 8, "dehaze.blur_levels", "a whole number in [0, 8]", blur_levels);
  RequireParam(guided_radius >= 0 && guided_radius <= 255, "dehaze.guided_radius", "a whole number in [0, 255]",
               guided_radius);
  RequireParam(guided_eps > 0.0, "dehaze.guided_eps", "a value > 0", guided_eps);
}

cv::Mat DarkChannel(const cv::Mat& image, int window, const cv::Scalar& airlight) {
  // The window minimum commutes with the per-channel scaling and the channel
  // minimum, so erode on the native type (fast for 8 bit) and scale after.
  return DarkFromEroded(ErodedBlueGreen(image, window), FullOf(image), airlight);
}

cv::Scalar EstimateAirlight(const cv::Mat& image, const cv::Mat& dark, double fraction) {
  // Threshold at the (1 - fraction) quantile of the dark channel via a 1024-bin histogram.
  constexpr int kBins = 1024;
  std::vector<int> hist(kBins, 0);
  double sampled = 0;
  for (int y = 0; y < dark.rows; y += 2) {  // every 2nd pixel is plenty for a quantile
    const float* d = dark.ptr<float>(y);
    for (int x = 0; x < dark.cols; x += 2, ++sampled)
      ++hist[std::clamp(static_cast<int>(d[x] * (kBins - 1)), 0, kBins - 1)];
  }
  const double wanted = std::max(1.0, fraction * sampled);
  int bin = kBins - 1;
  for (double count = hist[bin]; count < wanted && bin > 0;) count += hist[--bin];
  cv::Mat mask = dark >= static_cast<float>(bin) / (kBins - 1);
  return cv::mean(image, mask) / FullOf(image);
}

cv::Mat EstimateTransmission(const cv::Mat& image, const cv::Mat& guide, const cv::Scalar& airlight,
                             const DehazeParams& params) {
  return TransmissionFromDark(DarkChannel(image, params.window, airlight), guide, params);
}

namespace {

// J = (I - A) / max(t, t0) + A (eq. 25), in vectorised OpenCV passes.
cv::Mat Recover(const cv::Mat& image, const cv::Mat& t, const cv::Scalar& airlight, double t0) {
  cv::Mat inv_t;
  cv::max(t, t0, inv_t);
  cv::divide(1.0, inv_t, inv_t);
  const cv::Scalar a = airlight * FullScale(image);
  cv::Mat f;
  image.convertTo(f, CV_32F);
  f -= a;
  if (image.channels() == 3) {
    cv::Mat inv3;
    cv::merge(std::vector<cv::Mat>{inv_t, inv_t, inv_t}, inv3);
    cv::multiply(f, inv3, f);
  } else {
    cv::multiply(f, inv_t, f);
  }
  f += a;
  cv::Mat out;
  f.convertTo(out, image.type());  // rounded and saturated
  return out;
}

}  // namespace

cv::Mat Dehaze(const cv::Mat& image, const DehazeParams& params, bool* applied) {
  params.Validate();
  RequireSupportedImage(image, "dehaze");
  const bool hazy = !params.gate || LaplacianVariance(image, params.blur_levels) < params.blur_threshold;
  if (applied) *applied = hazy;
  if (!hazy) return image.clone();

  // Haze varies slowly across a seabed frame, so the dark channel, airlight
  // and transmission are estimated at quarter resolution (window and guided
  // filter radius scaled alike) and only the recovery runs at full size:
  // about 4x cheaper than a full-resolution estimate.
  const int f = std::min(image.cols, image.rows) >= 64 ? 4 : 1;
  cv::Mat small = image;
  if (f > 1) cv::resize(image, small, cv::Size(image.cols / f, image.rows / f), 0, 0, cv::INTER_AREA);
  const int window = std::max(1, params.window / f) | 1;
  const std::vector<cv::Mat> eroded = ErodedBlueGreen(small, window);
  const double full = FullScale(image);
  const cv::Scalar airlight =
      EstimateAirlight(small, DarkFromEroded(eroded, full, cv::Scalar::all(1.0)), params.airlight_fraction);
  cv::Mat gray = small, guide;
  if (small.channels() == 3) cv::cvtColor(small, gray, cv::COLOR_BGR2GRAY);
  gray.convertTo(guide, CV_32F, 1.0 / full);
  cv::Mat t = 1.0 - params.omega * DarkFromEroded(eroded, full, airlight);
  if (params.guided_radius > 0) t = GuidedFilter(guide, t, std::max(1, params.guided_radius / f), params.guided_eps, 1);
  if (f > 1) cv::resize(t, t, image.size(), 0, 0, cv::INTER_LINEAR);
  return Recover(image, t, airlight, params.t0);
}

}  // namespace seamap
