#include "core/terrain/line_of_sight.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace seamap {

namespace {

// The highest height over blocks of `b` cells and one cell around each (a
// bilinear sample inside a block reads cells up to one past its last).
cv::Mat1f BlockMax(const cv::Mat1f& heights, int b) {
  const int rows = heights.rows, cols = heights.cols;
  const float none = -std::numeric_limits<float>::infinity();
  cv::Mat1f out((rows + b - 1) / b, (cols + b - 1) / b, none);
  for (int br = 0; br < out.rows; ++br)
    for (int bc = 0; bc < out.cols; ++bc) {
      float m = none;
      for (int r = std::max(0, br * b - 1); r <= std::min(rows - 1, (br + 1) * b + 1); ++r) {
        const float* h = heights[r];
        for (int c = std::max(0, bc * b - 1); c <= std::min(cols - 1, (bc + 1) * b + 1); ++c)
          if (std::isfinite(h[c])) m = std::max(m, h[c]);
      }
      out(br, bc) = m;
    }
  return out;
}

}  // namespace

LineOfSight::LineOfSight(const HeightGrid& grid) : grid_(grid) {
  if (grid_.empty()) return;
  block_max_ = BlockMax(grid_.height_m, kBlockCells);
  super_max_ = BlockMax(grid_.height_m, kSuperBlockCells);
  double highest = 0;
  cv::minMaxLoc(super_max_, nullptr, &highest);
  highest_m_ = highest;
}

bool LineOfSight::Height(double east_m, double north_m, double* up_m) const {
  return grid_.HeightAtCell((grid_.north0_m - north_m) / grid_.cell_m, (east_m - grid_.east0_m) / grid_.cell_m, up_m);
}

bool LineOfSight::Clear(const Eigen::Vector3d& point, const Eigen::Vector3d& eye, double tolerance_m) const {
  const Eigen::Vector3d d = eye - point;
  if (!(d.z() > 0)) return false;
  const double length = std::hypot(d.x(), d.y());  // horizontal
  if (grid_.empty() || !(length > 1e-9)) return true;
  const double rise = d.z() / length;  // metres up per metre along
  const double cell = grid_.cell_m;
  // Along the line in cell coordinates (columns east, rows south) per metre.
  const double dcol = d.x() / length / cell, drow = -d.y() / length / cell;
  const double col0 = (point.x() - grid_.east0_m) / cell, row0 = (grid_.north0_m - point.y()) / cell;
  const double step = cell / 2;
  // Metres along the line until it leaves block (br, bc) of `b` cells, from (row, col).
  auto to_exit = [&](double row, double col, int br, int bc, double b) {
    const double to_col = dcol > 0 ? ((bc + 1) * b - col) / dcol : dcol < 0 ? (col - bc * b) / -dcol : 1e300;
    const double to_row = drow > 0 ? ((br + 1) * b - row) / drow : drow < 0 ? (row - br * b) / -drow : 1e300;
    return std::min(to_col, to_row) + 1e-6;  // a micrometre past the edge
  };
  // From half a cell off the point (the surface there is the point's own).
  for (double s = step; s < length;) {
    const double z = point.z() + s * rise;
    if (z > highest_m_ + tolerance_m) return true;
    const double col = col0 + s * dcol, row = row0 + s * drow;
    if (!(row >= 0 && col >= 0 && row <= grid_.rows() - 1 && col <= grid_.cols() - 1))
      return true;  // off the grid: a straight line from a point on it does not come back
    // Above the whole (super)block, and rising: go on from where the line leaves it.
    const int sr = static_cast<int>(row) / kSuperBlockCells, sc = static_cast<int>(col) / kSuperBlockCells;
    if (z > super_max_(sr, sc) + tolerance_m) {
      s += to_exit(row, col, sr, sc, kSuperBlockCells);
      continue;
    }
    const int br = static_cast<int>(row) / kBlockCells, bc = static_cast<int>(col) / kBlockCells;
    if (z > block_max_(br, bc) + tolerance_m) {
      s += to_exit(row, col, br, bc, kBlockCells);
      continue;
    }
    double h = 0;
    if (Height(point.x() + s * d.x() / length, point.y() + s * d.y() / length, &h) && h > z + tolerance_m) return false;
    s += step;
  }
  return true;
}

}  // namespace seamap
