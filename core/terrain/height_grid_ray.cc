#include "core/terrain/height_grid_ray.h"

#include <algorithm>
#include <cmath>

namespace seamap {
namespace {

constexpr double kHitTolerance_m = 1e-4;
constexpr double kMinStepCells = 0.5;
constexpr int kBlockCells = 4;
constexpr int kSuperCells = 16;  // a whole number of blocks

}  // namespace

HeightGridRayCaster::HeightGridRayCaster(const HeightGrid& grid) : grid_(grid) {
  const cv::Mat1f& h = grid_.height_m;
  const int block_rows = (h.rows + kBlockCells - 1) / kBlockCells,
            block_cols = (h.cols + kBlockCells - 1) / kBlockCells;
  block_max_ = cv::Mat1f(block_rows, block_cols, -INFINITY);
  block_slope_ = cv::Mat1f(block_rows, block_cols, 0.f);
  double lo = INFINITY, hi = -INFINITY, slope2 = 0;
  for (int r = 0; r < h.rows; ++r)
    for (int c = 0; c < h.cols; ++c) {
      const float v = h(r, c);
      if (!std::isfinite(v)) continue;
      lo = std::min<double>(lo, v), hi = std::max<double>(hi, v);
      // A cell on a block's south or east edge also bounds the block before it.
      for (int br = (r - 1) / kBlockCells; br <= r / kBlockCells; ++br)
        for (int bc = (c - 1) / kBlockCells; bc <= c / kBlockCells; ++bc)
          if (br >= 0 && bc >= 0 && br < block_rows && bc < block_cols)
            block_max_(br, bc) = std::max(block_max_(br, bc), v);
      // Inside a bilinear cell each gradient component is a blend of the
      // cell's two edge differences: bounded by the larger one.
      if (r + 1 < h.rows && c + 1 < h.cols) {
        const float v01 = h(r, c + 1), v10 = h(r + 1, c), v11 = h(r + 1, c + 1);
        if (!std::isfinite(v01) || !std::isfinite(v10) || !std::isfinite(v11)) continue;
        const double gx = std::max(std::fabs(v01 - v), std::fabs(v11 - v10));
        const double gy = std::max(std::fabs(v10 - v), std::fabs(v11 - v01));
        const double g2 = gx * gx + gy * gy;
        slope2 = std::max(slope2, g2);
        float& block = block_slope_(r / kBlockCells, c / kBlockCells);
        // A little margin for float rounding.
        block = std::max(block, static_cast<float>(std::sqrt(g2) / grid_.cell_m * 1.001 + 1e-6));
      }
    }
  constexpr int kPerSuper = kSuperCells / kBlockCells;
  super_max_ = cv::Mat1f((block_rows + kPerSuper - 1) / kPerSuper, (block_cols + kPerSuper - 1) / kPerSuper, -INFINITY);
  for (int br = 0; br < block_rows; ++br)
    for (int bc = 0; bc < block_cols; ++bc) {
      float& super = super_max_(br / kPerSuper, bc / kPerSuper);
      super = std::max(super, block_max_(br, bc));
    }
  min_height_m_ = std::isfinite(lo) ? lo : 0;
  max_height_m_ = std::isfinite(hi) ? hi : 0;
  max_slope_ = grid_.empty() ? 0 : std::sqrt(slope2) / grid_.cell_m * 1.001 + 1e-6;
}

bool HeightGridRayCaster::Height(double east_m, double north_m, double* up_m) const {
  return HeightAtCell((north0_m() - north_m) / grid_.cell_m, (east_m - grid_.east0_m) / grid_.cell_m, up_m);
}

bool HeightGridRayCaster::HeightAtCell(double row, double col, double* up_m) const {
  return grid_.HeightAtCell(row, col, up_m);
}

bool HeightGridRayCaster::Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double* t_out) const {
  if (grid_.empty() || !(d.z() < 0)) return false;
  const double descent = -d.z();
  const double horizontal = std::sqrt(d.x() * d.x() + d.y() * d.y());
  // The ray in fractional cell indices: col = col0 + t dcol, row = row0 + t drow.
  const double inv_cell = 1 / grid_.cell_m;
  const double col0 = (origin.x() - grid_.east0_m) * inv_cell, dcol = d.x() * inv_cell;
  const double row0 = (grid_.north0_m - origin.y()) * inv_cell, drow = -d.y() * inv_cell;
  const double inv_dcol = dcol != 0 ? 1 / dcol : 0, inv_drow = drow != 0 ? 1 / drow : 0;
  const double nudge = 1e-4 / (std::fabs(dcol) + std::fabs(drow) + 1e-12);  // 1e-4 cell along the ray
  // Steps no shorter than half a cell along the ray, so that a ray grazing
  // a slope does not crawl; a step that ends under the surface is refined.
  const double min_step = kMinStepCells * grid_.cell_m / std::sqrt(horizontal * horizontal + descent * descent);
  const double tolerance = kHitTolerance_m;
  const auto gap_at = [&](double t, double* gap) {
    double h = 0;
    if (!HeightAtCell(row0 + t * drow, col0 + t * dcol, &h)) return false;
    *gap = origin.z() + t * d.z() - h;
    return true;
  };
  // Nothing to hit above the highest cell: start there.
  double t = std::max(0.0, (origin.z() - max_height_m_) / descent);
  const double t_end = (origin.z() - min_height_m_) / descent + tolerance / descent;
  double gap = 0;
  bool gap_known = false;
  while (t <= t_end) {
    // The block holding the ray at t, and where the ray leaves it.
    const double col = col0 + t * dcol, row = row0 + t * drow;
    if (!(col >= 0 && row >= 0)) return false;
    const int cell_col = static_cast<int>(col), cell_row = static_cast<int>(row);
    if (cell_row / kBlockCells >= block_max_.rows || cell_col / kBlockCells >= block_max_.cols) return false;
    // Where the ray leaves the square of `size` cells holding it.
    const auto exit_of = [&](int size, int sr, int sc) {
      double exit = INFINITY;
      if (dcol > 0) exit = std::min(exit, ((sc + 1) * size - col0) * inv_dcol);
      if (dcol < 0) exit = std::min(exit, (sc * size - col0) * inv_dcol);
      if (drow > 0) exit = std::min(exit, ((sr + 1) * size - row0) * inv_drow);
      if (drow < 0) exit = std::min(exit, (sr * size - row0) * inv_drow);
      return exit;
    };
    // The ray is lowest where it leaves a square: above the square's highest
    // cell there, it cannot meet the surface in it. Superblocks first.
    const int sr = cell_row / kSuperCells, sc = cell_col / kSuperCells;
    const double t_super_exit = exit_of(kSuperCells, sr, sc);
    if (origin.z() + t_super_exit * d.z() > super_max_(sr, sc)) {
      t = t_super_exit + nudge;
      gap_known = false;
      continue;
    }
    const int br = cell_row / kBlockCells, bc = cell_col / kBlockCells;
    const double t_exit = exit_of(kBlockCells, br, bc);
    if (origin.z() + t_exit * d.z() > block_max_(br, bc)) {
      t = t_exit + nudge;
      gap_known = false;
      continue;
    }
    // Down to the block's highest cell the ray is free: no look-up needed.
    const double t_free = (origin.z() - block_max_(br, bc)) / descent;
    if (t_free > t) t = t_free, gap_known = false;
    if (!gap_known && !gap_at(t, &gap)) return false;
    gap_known = true;
    if (gap < 0 && t == 0) return false;  // starts below the surface
    // (Below by a nudge just past a skipped block's edge: that edge is the hit.)
    if (gap < tolerance) {
      *t_out = t;
      return true;
    }
    // Conservative step within the block: its slope bounds how fast the gap can shrink.
    const double closing = descent + block_slope_(br, bc) * horizontal;
    double t_next = t + std::max(gap / closing, min_step);
    if (t_next > t_exit + nudge) t_next = std::max(t_exit + nudge, t + min_step);
    double gap_next = 0;
    if (!gap_at(t_next, &gap_next)) return false;
    if (gap_next >= 0) {
      t = t_next, gap = gap_next;
      continue;
    }
    // Crossed between t (above) and t_next (below): regula falsi (Illinois).
    double lo = t, g_lo = gap, hi = t_next, g_hi = gap_next;
    int side = 0;
    for (int i = 0; i < 60 && (hi - lo) * descent > tolerance; ++i) {
      const double mid = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
      double g = 0;
      if (!gap_at(mid, &g)) return false;
      if (std::fabs(g) < tolerance) {
        *t_out = mid;
        return true;
      }
      if (g > 0) {
        lo = mid, g_lo = g;
        if (side == 1) g_hi /= 2;
        side = 1;
      } else {
        hi = mid, g_hi = g;
        if (side == -1) g_lo /= 2;
        side = -1;
      }
    }
    *t_out = lo;
    return true;
  }
  return false;
}

}  // namespace seamap
