#pragma once
// Constructed test images for the enhancement tests (the survey simulator is
// not used here, so each test controls exactly what degradation it adds).
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace seamap::testing {

// Seabed-like texture in [lo, hi]: multi-scale noise plus dark and bright pebbles,
// so every 15-20 px window holds both dark and bright pixels.
inline cv::Mat Texture(cv::Size size, int seed, double lo = 0.05, double hi = 0.95) {
  cv::RNG rng(seed);
  cv::Mat acc = cv::Mat::zeros(size, CV_32F);
  double amp = 1.0;
  for (int cell = 64; cell >= 2; cell /= 2) {
    cv::Mat small(size.height / cell + 2, size.width / cell + 2, CV_32F), up;
    rng.fill(small, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::resize(small, up, cv::Size(small.cols * cell, small.rows * cell), 0, 0, cv::INTER_CUBIC);
    acc += amp * up(cv::Rect(cv::Point(), size));
    amp *= 0.8;
  }
  cv::normalize(acc, acc, 0.3, 0.7, cv::NORM_MINMAX);
  const int pebbles = size.area() / 60;
  for (int i = 0; i < pebbles; ++i) {
    cv::Point c(rng.uniform(0, size.width), rng.uniform(0, size.height));
    cv::circle(acc, c, rng.uniform(2, 6), cv::Scalar(i % 2 ? 0.0 : 1.0), -1, cv::LINE_AA);
  }
  acc = lo + acc * (hi - lo);
  return acc;
}

// BGR texture with per-channel variation (same structure in all channels).
inline cv::Mat ColorTexture(cv::Size size, int seed) {
  cv::Mat t = Texture(size, seed);
  cv::Mat out;
  cv::merge(std::vector<cv::Mat>{t * 0.9 + 0.05, t, t * 0.8 + 0.1}, out);
  return out;
}

// Unit-range float -> a supported type, with the same channel count.
inline cv::Mat ToType(const cv::Mat& unit, int depth) {
  cv::Mat out;
  unit.convertTo(out, depth, depth == CV_16U ? 65535.0 : 255.0);
  return out;
}

inline cv::Mat ToUnit(const cv::Mat& image) {
  cv::Mat out;
  image.convertTo(out, CV_32F, image.depth() == CV_16U ? 1.0 / 65535.0 : 1.0 / 255.0);
  return out;
}

// Lamp falloff: 1 at the centre, 1 - depth at the corners (quadratic in radius).
inline cv::Mat RadialFalloff(cv::Size size, double depth) {
  cv::Mat f(size, CV_32F);
  const double half_diag = std::hypot(size.width / 2.0, size.height / 2.0);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      double r = std::hypot(x + 0.5 - size.width / 2.0, y + 0.5 - size.height / 2.0) / half_diag;
      f.at<float>(y, x) = static_cast<float>(1.0 - depth * r * r);
    }
  return f;
}

inline cv::Mat Multiply(const cv::Mat& image, const cv::Mat& gain1) {
  cv::Mat g = gain1;
  if (image.channels() == 3) cv::merge(std::vector<cv::Mat>{gain1, gain1, gain1}, g);
  return image.mul(g);
}

inline double MeanIn(const cv::Mat& m, const cv::Rect& r) {
  return cv::mean(m(r))[0];
}

}  // namespace seamap::testing
