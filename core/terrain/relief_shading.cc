#include "core/terrain/relief_shading.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace seamap {

// Deep blue, blue, cyan-green, green, sand, brown: dark for deep, warm for
// high, as bathymetric charts read; legible on the photo map and for the
// common colour-vision deficiencies (lightness rises then falls monotonically
// enough that the hillshade stays readable).
const std::array<std::array<uint8_t, 3>, kReliefRampStops> kReliefRampRgb = {{
    {{33, 49, 140}},
    {{44, 123, 182}},
    {{78, 179, 160}},
    {{166, 217, 106}},
    {{240, 200, 110}},
    {{166, 97, 26}},
}};

ReliefStyle ReliefStyleFor(const HeightGrid& grid) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const float h = grid.height_m(r, c);
      if (!std::isfinite(h)) continue;
      lo = std::min<double>(lo, h);
      hi = std::max<double>(hi, h);
    }
  ReliefStyle style;
  if (!std::isfinite(lo)) return style;
  if (hi - lo < 0.01) {
    const double mid = 0.5 * (lo + hi);
    lo = mid - 0.005;
    hi = mid + 0.005;
  }
  style.low_m = lo;
  style.high_m = hi;
  return style;
}

cv::Vec3b RampColour(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  const double x = t * (kReliefRampStops - 1);
  const int i = std::min(static_cast<int>(x), kReliefRampStops - 2);
  const double f = x - i;
  cv::Vec3b bgr;
  for (int k = 0; k < 3; ++k) {
    const double v = (1 - f) * kReliefRampRgb[i][k] + f * kReliefRampRgb[i + 1][k];
    bgr[2 - k] = static_cast<uint8_t>(std::lround(v));
  }
  return bgr;
}

namespace {

// d height / d index along one axis, one-sided next to a hole or the edge; 0 alone.
double Derivative(const cv::Mat1f& h, int r, int c, int dr, int dc) {
  const auto at = [&](int rr, int cc, double* v) {
    if (rr < 0 || cc < 0 || rr >= h.rows || cc >= h.cols) return false;
    *v = h(rr, cc);
    return std::isfinite(*v);
  };
  double centre = h(r, c), before = 0, after = 0;
  const bool has_before = at(r - dr, c - dc, &before), has_after = at(r + dr, c + dc, &after);
  if (has_before && has_after) return 0.5 * (after - before);
  if (has_after) return after - centre;
  if (has_before) return centre - before;
  return 0;
}

// Heights smoothed by a normalised Gaussian (holes and the outside weigh
// nothing, so a hole does not drag its neighbours down); NaN stays NaN.
cv::Mat1f SmoothHeights(const cv::Mat1f& height, double sigma_cells) {
  if (!(sigma_cells > 0)) return height;
  cv::Mat1f filled(height.size()), valid(height.size());
  for (int r = 0; r < height.rows; ++r)
    for (int c = 0; c < height.cols; ++c) {
      const bool ok = std::isfinite(height(r, c));
      filled(r, c) = ok ? height(r, c) : 0.f;
      valid(r, c) = ok ? 1.f : 0.f;
    }
  // Relative to the mean height: float32 keeps the smoothing exact to the micrometre at 35 m depth.
  const double mean = cv::sum(filled)[0] / std::max(1.0, cv::sum(valid)[0]);
  filled -= static_cast<float>(mean);
  filled = filled.mul(valid);
  cv::Mat1f sum, weight;
  cv::GaussianBlur(filled, sum, cv::Size(), sigma_cells, sigma_cells, cv::BORDER_CONSTANT);
  cv::GaussianBlur(valid, weight, cv::Size(), sigma_cells, sigma_cells, cv::BORDER_CONSTANT);
  cv::Mat1f out(height.size());
  for (int r = 0; r < height.rows; ++r)
    for (int c = 0; c < height.cols; ++c)
      out(r, c) = valid(r, c) > 0 ? static_cast<float>(sum(r, c) / weight(r, c) + mean) : NAN;
  return out;
}

}  // namespace

cv::Mat4b ShadeRelief(const HeightGrid& grid, const ReliefStyle& style) {
  cv::Mat4b out(grid.rows(), grid.cols(), cv::Vec4b(0, 0, 0, 0));
  const double az = style.sun_azimuth_deg * M_PI / 180, el = style.sun_elevation_deg * M_PI / 180;
  const double light_e = std::sin(az) * std::cos(el), light_n = std::cos(az) * std::cos(el), light_u = std::sin(el);
  const double span = style.high_m - style.low_m;
  const cv::Mat1f smooth = SmoothHeights(grid.height_m, style.smooth_cells);
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const float h = grid.height_m(r, c);
      if (!std::isfinite(h)) continue;
      // Rows run south: d/d north = -d/d row.
      const double dh_de = style.z_factor * Derivative(smooth, r, c, 0, 1) / grid.cell_m;
      const double dh_dn = -style.z_factor * Derivative(smooth, r, c, 1, 0) / grid.cell_m;
      const double norm = std::sqrt(dh_de * dh_de + dh_dn * dh_dn + 1);
      const double shade = std::max(0.0, (-dh_de * light_e - dh_dn * light_n + light_u) / norm);
      const cv::Vec3b colour = RampColour(span > 0 ? (h - style.low_m) / span : 0.5);
      const double gain = 0.4 + 0.6 * shade;
      out(r, c) = cv::Vec4b(cv::saturate_cast<uint8_t>(colour[0] * gain), cv::saturate_cast<uint8_t>(colour[1] * gain),
                            cv::saturate_cast<uint8_t>(colour[2] * gain), 255);
    }
  return out;
}

}  // namespace seamap
