#include "core/terrain/height_grid_ray.h"

#include <algorithm>
#include <cmath>

namespace seamap {
namespace {

constexpr double kHitTolerance_m = 1e-5;
constexpr double kMinStepCells = 0.25;

}  // namespace

HeightGridRayCaster::HeightGridRayCaster(const HeightGrid& grid) : grid_(grid) {
  double lo = INFINITY, hi = -INFINITY, slope2 = 0;
  const cv::Mat1f& h = grid_.height_m;
  for (int r = 0; r < h.rows; ++r)
    for (int c = 0; c < h.cols; ++c) {
      const float v = h(r, c);
      if (!std::isfinite(v)) continue;
      lo = std::min<double>(lo, v), hi = std::max<double>(hi, v);
      // Inside a bilinear cell each gradient component is a blend of the
      // cell's two edge differences: bounded by the larger one.
      if (r + 1 < h.rows && c + 1 < h.cols) {
        const float v01 = h(r, c + 1), v10 = h(r + 1, c), v11 = h(r + 1, c + 1);
        if (!std::isfinite(v01) || !std::isfinite(v10) || !std::isfinite(v11)) continue;
        const double gx = std::max(std::fabs(v01 - v), std::fabs(v11 - v10));
        const double gy = std::max(std::fabs(v10 - v), std::fabs(v11 - v01));
        slope2 = std::max(slope2, gx * gx + gy * gy);
      }
    }
  min_height_m_ = std::isfinite(lo) ? lo : 0;
  max_height_m_ = std::isfinite(hi) ? hi : 0;
  // A little margin for float rounding.
  max_slope_ = grid_.empty() ? 0 : std::sqrt(slope2) / grid_.cell_m * 1.001 + 1e-9;
}

bool HeightGridRayCaster::Height(double east_m, double north_m, double* up_m) const {
  const double col = (east_m - grid_.east0_m) / grid_.cell_m;
  const double row = (grid_.north0_m - north_m) / grid_.cell_m;
  const int rows = grid_.rows(), cols = grid_.cols();
  if (!(row >= 0 && col >= 0 && row <= rows - 1 && col <= cols - 1)) return false;
  const int r0 = std::min(static_cast<int>(row), std::max(rows - 2, 0));
  const int c0 = std::min(static_cast<int>(col), std::max(cols - 2, 0));
  const int r1 = std::min(r0 + 1, rows - 1), c1 = std::min(c0 + 1, cols - 1);
  const double fr = row - r0, fc = col - c0;
  const float* a = grid_.height_m[r0];
  const float* b = grid_.height_m[r1];
  const double h = (1 - fr) * ((1 - fc) * a[c0] + fc * a[c1]) + fr * ((1 - fc) * b[c0] + fc * b[c1]);
  if (!std::isfinite(h)) return false;
  *up_m = h;
  return true;
}

bool HeightGridRayCaster::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double* t_out) const {
  if (grid_.empty() || !(d.z() < 0)) return false;
  const double descent = -d.z();
  const double horizontal = std::hypot(d.x(), d.y());
  const double closing = descent + max_slope_ * horizontal;  // fastest the gap can shrink per unit t
  // Steps no shorter than a quarter cell along the ray, so that a ray grazing
  // a slope does not crawl; a step that ends under the surface is bisected.
  const double min_step = kMinStepCells * grid_.cell_m / d.norm();
  const auto gap_at = [&](double t, double* gap) {
    const Eigen::Vector3d p = origin + t * d;
    double h = 0;
    if (!Height(p.x(), p.y(), &h)) return false;
    *gap = p.z() - h;
    return true;
  };
  // Nothing to hit above the highest cell: start there.
  double t = std::max(0.0, (origin.z() - max_height_m_) / descent);
  const double t_end = (origin.z() - min_height_m_) / descent + kHitTolerance_m / descent;
  double gap = 0;
  if (!gap_at(t, &gap) || gap < 0) return false;  // off the grid, or starts below the surface
  while (gap >= kHitTolerance_m) {
    const double t_next = t + std::max(gap / closing, min_step);
    if (t_next > t_end + min_step) return false;
    double gap_next = 0;
    if (!gap_at(t_next, &gap_next)) return false;
    if (gap_next < 0) {
      // Crossed between t (above) and t_next (below).
      double lo = t, hi = t_next;
      for (int i = 0; i < 40 && (hi - lo) * descent > kHitTolerance_m; ++i) {
        const double mid = (lo + hi) / 2;
        double g = 0;
        if (!gap_at(mid, &g)) return false;
        (g < 0 ? hi : lo) = mid;
      }
      *t_out = lo;
      return true;
    }
    t = t_next, gap = gap_next;
  }
  *t_out = t;
  return true;
}

}  // namespace seamap
