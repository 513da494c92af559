#pragma once
// Where a ray first meets a height model (height_grid.h) coming from above:
// what the simulator renders frames and DVL beams with, and what a
// projection onto a surface needs. First hit means occlusion is exact: a
// ray grazing a bump stops on the bump.
//
// Method: conservative marching (sphere tracing for a height field) over
// blocks of 4 x 4 cells. A block (or a superblock of 4 x 4 blocks) whose
// highest cell lies below the ray where the ray leaves it is skipped whole. Within a block the bilinear
// surface has a slope no steeper than the block's bound, so from a point
// `gap` metres above the surface the ray can advance
// gap / (descent + slope * horizontal) of its length without crossing it;
// the steps shrink geometrically towards the first hit and can never step
// over a ridge. Steps are at least half a cell long (a grazing ray would
// otherwise crawl); one that ends under the surface is refined by regula
// falsi. So a ridge thinner than half a cell may be stepped through; the
// hit is within 0.1 mm (vertically) of the surface.
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
  // Bilinear height at fractional cell indices.
  bool HeightAtCell(double row, double col, double* up_m) const;
  double north0_m() const { return grid_.north0_m; }

  HeightGrid grid_;
  double min_height_m_ = 0, max_height_m_ = 0, max_slope_ = 0;
  // Per block of 4 x 4 cells: the highest height (rays passing above it
  // skip the block) and the slope bound (steps within it).
  cv::Mat1f block_max_, block_slope_;
  cv::Mat1f super_max_;  // highest height per 16 x 16 cells (4 x 4 blocks)
};

}  // namespace seamap
