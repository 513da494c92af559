#include "core/sim/seabed_texture.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

// Smooth gaussian noise with features about `wavelength_px` across: a coarse
// random grid upsampled with bicubic interpolation.
cv::Mat1f SmoothNoise(cv::Size size, double wavelength_px, cv::RNG& rng) {
  cv::Mat1f grid(static_cast<int>(std::ceil(size.height / wavelength_px)) + 3,
                 static_cast<int>(std::ceil(size.width / wavelength_px)) + 3);
  rng.fill(grid, cv::RNG::NORMAL, 0, 1);
  cv::Mat1f up;
  cv::resize(grid, up, size, 0, 0, cv::INTER_CUBIC);
  return up;
}

// Scales to zero mean, unit deviation; returns the scale factor.
double NormaliseToUnit(cv::Mat1f& m) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(m, mean, stddev);
  const double scale = 1 / std::max(stddev[0], 1e-9);
  m.convertTo(m, CV_32F, scale, -mean[0] * scale);
  return scale;
}

cv::Size LevelSize(cv::Size size, int level) {
  return {std::max(1, (size.width + (1 << level) - 1) >> level),
          std::max(1, (size.height + (1 << level) - 1) >> level)};
}

// Sand ripples: crests `wavelength_m` apart, bent by low-frequency noise and
// present only in patches. `res_m` is the pixel size of `img`.
void AddRipples(cv::Mat1f& img, double res_m, double wavelength_m, double angle, cv::RNG& rng) {
  cv::Mat1f warp = SmoothNoise(img.size(), 1.0 / res_m, rng);
  cv::Mat1f patch = SmoothNoise(img.size(), 3.0 / res_m, rng);
  const double kx = 2 * M_PI * std::cos(angle) * res_m / wavelength_m;
  const double ky = 2 * M_PI * std::sin(angle) * res_m / wavelength_m;
  cv::parallel_for_(cv::Range(0, img.rows), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      float* out = img[y];
      const float* w = warp[y];
      const float* p = patch[y];
      for (int x = 0; x < img.cols; ++x) {
        const double phase = kx * x + ky * y + 2.5 * w[x];
        const double presence = std::clamp(0.3 + 0.9 * p[x], 0.0, 1.0);  // patchy
        // Asymmetric profile sin(p) + 0.35 sin(2p): steep lee side, gentle stoss side.
        out[x] += static_cast<float>(1.0 * presence * std::sin(phase) * (1 + 0.7 * std::cos(phase)));
      }
    }
  });
}

// Rocks and shells: filled ellipses with a shadow towards the south-east and
// a highlight towards the north-west, added to the texture so that the fine
// noise stays visible on them.
void AddStones(cv::Mat1f& img, double res_m, double per_m2, double r_min_m, double r_max_m, double brightness,
               cv::RNG& rng) {
  const double area_m2 = img.total() * res_m * res_m;
  const int count = static_cast<int>(area_m2 * per_m2);
  for (int k = 0; k < count; ++k) {
    const double r = std::exp(rng.uniform(std::log(r_min_m), std::log(r_max_m))) / res_m;
    const cv::Size2f axes(static_cast<float>(r), static_cast<float>(r * rng.uniform(0.45, 1.0)));
    const float angle = static_cast<float>(rng.uniform(0.0, 180.0));
    const double body = brightness + rng.gaussian(0.8);
    const cv::Point2f centre(static_cast<float>(rng.uniform(0.0, 1.0 * img.cols)),
                             static_cast<float>(rng.uniform(0.0, 1.0 * img.rows)));
    const int half = static_cast<int>(std::ceil(r * 1.4)) + 2;
    const cv::Rect box =
        cv::Rect(static_cast<int>(centre.x) - half, static_cast<int>(centre.y) - half, 2 * half + 1, 2 * half + 1) &
        cv::Rect(0, 0, img.cols, img.rows);
    if (box.empty()) continue;
    cv::Mat1f layer(box.size(), 0.f);
    const cv::Point2f c = centre - cv::Point2f(static_cast<float>(box.x), static_cast<float>(box.y));
    const float shift = static_cast<float>(0.3 * r);
    cv::ellipse(layer, cv::RotatedRect(c + cv::Point2f(shift, shift), axes * 2.f, angle), cv::Scalar(-2.0), cv::FILLED);
    cv::ellipse(layer, cv::RotatedRect(c, axes * 2.f, angle), cv::Scalar(body), cv::FILLED);
    cv::ellipse(layer, cv::RotatedRect(c - cv::Point2f(shift, shift), axes, angle), cv::Scalar(body + 1.0), cv::FILLED);
    cv::GaussianBlur(layer, layer, cv::Size(), 0.8);  // soft edges
    img(box) += layer;
  }
}

void CheckBitDepth(int bit_depth) {
  if (bit_depth != 8 && bit_depth != 16)
    throw InputError("", 0, "--bit-depth", "expected 8 or 16, got " + std::to_string(bit_depth));
}

}  // namespace

cv::Mat MakeProceduralTexture(cv::Size size, double res_m, bool color, int bit_depth, uint64_t seed) {
  CheckBitDepth(bit_depth);
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 0x5eabed);
  // Noise octaves as a pyramid, coarse to fine: white noise added at level k
  // (1/2^k resolution) becomes features ~2^k pixels wide after the bicubic
  // upsamplings, from 2 pixels up to about 2 m; coarser ones a little stronger.
  int levels = 1;
  while ((2 << levels) * res_m <= 2.0 && levels < 14) ++levels;
  const double ripple_wavelength_m = rng.uniform(0.06, 0.09);
  const double ripple_angle = rng.uniform(0.0, M_PI);
  // Ripples are drawn at the coarsest level where they are still >= 24 pixels apart.
  int ripple_level = 0;
  while (ripple_level < levels && ripple_wavelength_m / (res_m * (2 << ripple_level)) >= 24) ++ripple_level;

  cv::Mat1f lum(LevelSize(size, levels), 0.f);
  double unit = 1;  // scale making the noise unit-variance once normalised
  for (int k = levels; k >= 1; --k) {
    cv::Mat1f white(lum.size());
    rng.fill(white, cv::RNG::NORMAL, 0, unit * std::pow(2.0, 0.2 * (k - 1)));
    lum += white;
    if (k == ripple_level) {
      unit *= NormaliseToUnit(lum);
      AddRipples(lum, res_m * (1 << k), ripple_wavelength_m, ripple_angle, rng);
    }
    cv::Mat1f up;
    cv::resize(lum, up, LevelSize(size, k - 1), 0, 0, cv::INTER_CUBIC);
    lum = up;
  }
  if (ripple_level == 0) {
    NormaliseToUnit(lum);
    AddRipples(lum, res_m, ripple_wavelength_m, ripple_angle, rng);
  }
  NormaliseToUnit(lum);
  AddStones(lum, res_m, 3.0, 0.03, 0.12, 0.0, rng);    // rocks, lighter or darker
  AddStones(lum, res_m, 25.0, 0.005, 0.02, 2.0, rng);  // pale shells and pebbles
  NormaliseToUnit(lum);
  const double max_value = bit_depth == 16 ? 65535.0 : 255.0;
  const int depth = bit_depth == 16 ? CV_16U : CV_8U;
  cv::Mat out;
  if (!color) {
    lum.convertTo(out, depth, 0.16 * max_value, 0.5 * max_value);
    // Nothing fully black or white: 0 is left for "outside the texture".
    cv::min(cv::max(out, 0.02 * max_value), 0.98 * max_value, out);
    return out;
  }
  // Sand tones drifting between brownish and greenish over metres; the mix
  // field is smooth, so it is kept at 1/16 resolution and interpolated here.
  constexpr int kMixStep = 16;
  const cv::Mat1f mix = SmoothNoise(LevelSize(size, 4), 2.0 / res_m / kMixStep, rng);
  const cv::Vec3f brown(0.62f, 0.80f, 0.95f), green(0.55f, 0.85f, 0.68f);  // BGR
  out.create(size, CV_MAKETYPE(depth, 3));
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float my = std::clamp((y + 0.5f) / kMixStep - 0.5f, 0.f, mix.rows - 1.f);
      const int y0 = std::min(static_cast<int>(my), std::max(0, mix.rows - 2));
      const int y1 = std::min(y0 + 1, mix.rows - 1);
      const float fy = my - y0;
      const float* l = lum[y];
      for (int x = 0; x < size.width; ++x) {
        const float mx = std::clamp((x + 0.5f) / kMixStep - 0.5f, 0.f, mix.cols - 1.f);
        const int x0 = std::min(static_cast<int>(mx), std::max(0, mix.cols - 2));
        const int x1 = std::min(x0 + 1, mix.cols - 1);
        const float fx = mx - x0;
        const float m =
            (1 - fy) * ((1 - fx) * mix(y0, x0) + fx * mix(y0, x1)) + fy * ((1 - fx) * mix(y1, x0) + fx * mix(y1, x1));
        const float w = std::clamp(0.5f + 0.4f * m, 0.f, 1.f);
        const float value = std::clamp(0.5f + 0.16f * l[x], 0.02f, 0.98f);
        const cv::Vec3f bgr = (brown * (1 - w) + green * w) * (1.1f * value * static_cast<float>(max_value));
        if (depth == CV_16U)
          out.ptr<cv::Vec3w>(y)[x] = cv::Vec3w(cv::saturate_cast<uint16_t>(bgr[0]), cv::saturate_cast<uint16_t>(bgr[1]),
                                               cv::saturate_cast<uint16_t>(bgr[2]));
        else
          out.ptr<cv::Vec3b>(y)[x] = cv::Vec3b(cv::saturate_cast<uint8_t>(bgr[0]), cv::saturate_cast<uint8_t>(bgr[1]),
                                               cv::saturate_cast<uint8_t>(bgr[2]));
      }
    }
  });
  return out;
}

cv::Mat LoadTextureImage(const std::string& path, bool color, int bit_depth) {
  CheckBitDepth(bit_depth);
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw InputError(path, 0, "--texture", "cannot read the image (missing or not an image)");
  if (img.depth() != CV_8U && img.depth() != CV_16U)
    throw InputError(path, 0, "--texture", "expected an 8 or 16-bit image");
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2BGR);
  if (color && img.channels() == 1) cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);
  if (!color && img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  const int depth = bit_depth == 16 ? CV_16U : CV_8U;
  if (img.depth() != depth) img.convertTo(img, CV_MAKETYPE(depth, img.channels()), depth == CV_16U ? 257.0 : 1 / 257.0);
  return img;
}

void SaveTruth(const SeabedTexture& texture, LatLon origin, const std::string& truth_dir) {
  std::filesystem::create_directories(truth_dir);
  const std::string png = truth_dir + "/texture.png";
  if (!cv::imwrite(png, texture.image)) throw InputError(png, 0, "", "cannot write the texture");
  const nlohmann::json j = {{"origin", {origin.lat, origin.lon}}, {"res_m", texture.res_m},
                            {"east_min", texture.east_min},       {"north_max", texture.north_max},
                            {"width", texture.image.cols},        {"height", texture.image.rows}};
  const std::string json_path = truth_dir + "/texture.json";
  std::ofstream out(json_path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(json_path, 0, "", "cannot write the texture georeference");
}

}  // namespace seamap
