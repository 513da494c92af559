#include "core/terrain/surface_ray.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace seamap {

double HighestHeight(const HeightGrid& grid, double east_min, double east_max, double north_min, double north_max) {
  double highest = std::numeric_limits<double>::quiet_NaN();
  if (grid.empty()) return highest;
  double r0 = 0, c0 = 0, r1 = 0, c1 = 0;
  grid.CellOf({east_min, north_max}, &r0, &c0);
  grid.CellOf({east_max, north_min}, &r1, &c1);
  const int row_first = std::max(0, static_cast<int>(std::floor(r0))),
            row_last = std::min(grid.rows() - 1, static_cast<int>(std::ceil(r1)));
  const int col_first = std::max(0, static_cast<int>(std::floor(c0))),
            col_last = std::min(grid.cols() - 1, static_cast<int>(std::ceil(c1)));
  for (int r = row_first; r <= row_last; ++r) {
    const float* h = grid.height_m[r];
    for (int c = col_first; c <= col_last; ++c)
      if (std::isfinite(h[c]) && !(h[c] <= highest)) highest = h[c];
  }
  return highest;
}

std::optional<Eigen::Vector3d> FirstSurfaceHit(const HeightGrid& grid, const Eigen::Vector3d& origin,
                                               const Eigen::Vector3d& direction, double max_range_m) {
  const double length = direction.norm();
  if (grid.empty() || !(length > 0)) return std::nullopt;
  const Eigen::Vector3d d = direction / length;
  const double step = grid.cell_m / 2;
  // Height of the ray above the surface at distance t (NaN over a hole or off the grid).
  auto above = [&](double t) {
    const Eigen::Vector3d p = origin + t * d;
    double h = 0;
    return grid.Sample({p.x(), p.y()}, &h) ? p.z() - h : std::numeric_limits<double>::quiet_NaN();
  };
  double t_prev = 0, a_prev = above(0);
  for (double t = step; t <= max_range_m + step; t += step) {
    const double a = above(t);
    if (a <= 0) {
      if (!(a_prev > 0)) {  // entered the surface from a hole: no crossing to refine
        if (!(a_prev == a_prev)) return origin + t * d;
        return origin + t_prev * d;  // started at or below the surface
      }
      double lo = t_prev, hi = t;  // above at lo, below at hi
      while (hi - lo > grid.cell_m * 1e-3) {
        const double mid = (lo + hi) / 2, am = above(mid);
        (am > 0 || !(am == am) ? lo : hi) = mid;
      }
      return origin + hi * d;
    }
    t_prev = t;
    a_prev = a;
  }
  return std::nullopt;
}

bool InSight(const HeightGrid& grid, const Eigen::Vector3d& point, const Eigen::Vector3d& eye, double ceiling_m,
             double tolerance_m) {
  const Eigen::Vector3d d = eye - point;
  const double horizontal = std::hypot(d.x(), d.y());
  if (!(d.z() > 0)) return false;  // the eye is not above the point
  // March along the horizontal in half-cell steps, from half a cell off the
  // point (the surface there is the point's own) to below the eye.
  const double step = grid.cell_m / 2;
  for (double s = step; s < horizontal; s += step) {
    const double f = s / horizontal;
    const double z = point.z() + f * d.z();
    if (z > ceiling_m) return true;
    double h = 0;
    if (grid.Sample({point.x() + f * d.x(), point.y() + f * d.y()}, &h) && h > z + tolerance_m) return false;
  }
  return true;
}

}  // namespace seamap
