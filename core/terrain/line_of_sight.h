#pragma once
// Whether a seabed point can be seen from a camera: the straight line
// between them stays above the height model (height_grid.h). What a true
// orthophoto needs: a map point is painted only from frames that see it.
//
// Method: march up the line from the point in half-cell steps, but skip
// whole blocks of cells at once where the line is above their highest
// height (max grids over blocks of 4 and of 16 cells, each with a cell of
// border for the bilinear surface between blocks: the line, rising, stays
// above the block until it leaves it); once above the grid's highest height
// the line is clear. Holes are transparent: they neither hide
// a point nor stop the line (where the model has no height, nothing is known
// to be in the way).
#include <Eigen/Core>

#include "core/terrain/height_grid.h"

namespace seamap {

class LineOfSight {
 public:
  static constexpr int kBlockCells = 4, kSuperBlockCells = 16;

  // Keeps a shallow copy of the grid's heights.
  explicit LineOfSight(const HeightGrid& grid);

  // Bilinear height at a local point: HeightGrid::Sample without the
  // sigma, fast (it is asked for every few map pixels of every frame).
  bool Height(double east_m, double north_m, double* up_m) const;

  // Whether `eye` sees `point` (east, north, up; the point on or just above
  // the surface): no height along the line between them is more than
  // `tolerance_m` above it. False when the eye is not above the point.
  bool Clear(const Eigen::Vector3d& point, const Eigen::Vector3d& eye, double tolerance_m = 0.005) const;

  const HeightGrid& grid() const { return grid_; }

 private:
  HeightGrid grid_;
  cv::Mat1f block_max_, super_max_;  // highest height over each block and a cell around it; -inf: holes only
  double highest_m_ = -1e300;        // over the whole grid
};

}  // namespace seamap
