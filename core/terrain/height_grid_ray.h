#pragma once
// Where a ray first meets a height model (height_grid.h) coming from above:
// what the simulator renders frames and DVL beams with, and what a
// projection onto a surface needs. First hit means occlusion is exact: a
// ray grazing a bump stops on the bump.
//
// Method: conservative marching (sphere tracing for a height field). The
// grid's bilinear surface has a slope no steeper than a bound computed once,
// so from a point `gap` metres above the surface the ray can advance
// gap / (descent + slope * horizontal) of its length without crossing it;
// the steps shrink geometrically towards the first hit and can never step
// over a ridge. Steps are at least a quarter cell long (a grazing ray would
// otherwise crawl); one that ends under the surface is bisected. So a
// ridge thinner than a quarter cell may be stepped through: the hit is
// within 10 um (vertically) of the surface.
#include <Eigen/Core>

#include "core/terrain/height_grid.h"

namespace seamap {

class HeightGridRayCaster {
 public:
  // Keeps a (shallow) copy of the grid; NaN holes stop rays (a miss).
  explicit HeightGridRayCaster(const HeightGrid& grid);

  // Ray origin + t * direction, in local (east, north, up) metres; the
  // direction need not be unit length (t is in its units). True with *t at
  // the first hit; false when the ray leaves the grid, reaches a hole, does
  // not go down or starts below the surface.
  bool Cast(const Eigen::Vector3d& origin_enu, const Eigen::Vector3d& direction_enu, double* t) const;

  // Bilinear height at a local point (HeightGrid::Sample without sigma).
  bool Height(double east_m, double north_m, double* up_m) const;

  const HeightGrid& grid() const { return grid_; }
  double min_height_m() const { return min_height_m_; }
  double max_height_m() const { return max_height_m_; }
  double max_slope() const { return max_slope_; }  // |gradient| bound of the bilinear surface

 private:
  HeightGrid grid_;
  double min_height_m_ = 0, max_height_m_ = 0, max_slope_ = 0;
};

}  // namespace seamap
