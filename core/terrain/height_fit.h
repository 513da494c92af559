#pragma once
// A height model fitted to triangulated seabed points (seabed_point.h):
//  - cell size: `cell_m`, or from the points' density (about 24 points
//    within a cell's radius), never finer than 8 ground pixels (`gsd_m`);
//  - per cell, a local plane through the points within `radius_cells`
//    (weights: a smooth kernel over distance times 1/sigma^2), started at
//    the weighted median and fitted by weighted least squares twice, each
//    time over the points within three robust spreads (median absolute
//    deviation) of the previous estimate, so a minority of outliers neither
//    pulls nor votes; the height is the plane at the cell centre, its sigma
//    the fit's covariance (sandwich form) scaled by the residuals when they
//    exceed the points' sigmas;
//  - calibration by hold-out: a grid fitted to four points in five predicts
//    the fifth; what their residuals hold beyond their sigmas and that
//    grid's (relief finer than a cell, between cell centres) is a floor
//    added in quadrature to every cell sigma (HeightFitReport::sigma_floor_m);
//  - outliers against the neighbourhood: after a first fit, a point further
//    than `outlier_sigmas` from the surface (its sigma, the cell's and the
//    local spread together) is dropped and the grid fitted again;
//  - holes: a cell with fewer than `min_points`, with its points off to one
//    side (an extrapolation, at the swath's edges) or a sigma above
//    `max_sigma_m` is a hole (NaN); holes no
//    wider than `max_fill_m` inside the swath are filled from their rims,
//    the sigma growing with the distance to data by the grid's slope spread;
//    cells outside the surveyed swath (the union of `swath` footprints) NaN.
#include <array>
#include <vector>

#include "core/geo/local_frame.h"
#include "core/terrain/height_grid.h"
#include "core/terrain/seabed_point.h"

namespace seamap {

struct HeightFitOptions {
  double cell_m = 0;            // --dem-cell: 0 chooses it from the point density
  double gsd_m = 0;             // ground sample distance; the automatic cell is at least 8 of it
  double radius_cells = 1.5;    // points within this many cells of a cell centre shape it
  int min_points = 4;           // fewer within the radius: a hole
  double outlier_sigmas = 4.0;  // a point further from the surface is dropped
  double max_fill_m = 0.5;      // holes up to about this wide inside the swath are interpolated
  double max_sigma_m = 0.05;    // --dem-max-sigma: a cell less certain than this is a hole
  void Check() const;           // InputError naming the option
};

struct HeightFitReport {
  double cell_m = 0;
  long points = 0, points_rejected = 0;
  double sigma_floor_m = 0;  // the hold-out's unseen error, added to every cell's sigma
  long cells_swath = 0;      // cells inside the surveyed swath
  long cells_estimated = 0;  // with a height from points
  long cells_filled = 0;     // interpolated over a small hole
  long cells_holes = 0;      // left NaN inside the swath
};

// swath: ground footprints of the frames (corners in order); empty: the
// swath is where the points are. The result is empty when there are no
// usable points. has_depth_datum is copied to the grid.
HeightGrid FitHeightGrid(const SeabedPoints& points, const std::vector<std::array<LocalXY, 4>>& swath,
                         bool has_depth_datum, const HeightFitOptions& options, HeightFitReport* report = nullptr);

// Cells outside `swath` (footprints, corners in order, convex or not) made
// holes; report's cells_swath and cells_holes counted anew. For a swath
// known better once the heights are (footprints on the fitted surface).
void ClipHeightGrid(const std::vector<std::vector<LocalXY>>& swath, HeightGrid* grid, HeightFitReport* report);

}  // namespace seamap
