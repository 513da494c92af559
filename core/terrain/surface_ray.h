#pragma once
// Rays against the height model (height_grid.h): where a camera's ray first
// meets the seabed, and whether a seabed point can be seen from a camera (the
// straight line between them does not pass below the surface). What a true
// orthophoto needs: each map point is painted only from frames that see it.
//
// Points are (east, north, up) in the mission's local metres, up on the
// grid's datum. Holes in the grid are transparent: they neither stop a ray
// nor hide a point.
#include <optional>

#include <Eigen/Core>

#include "core/terrain/height_grid.h"

namespace seamap {

// The highest height of the grid's cells within a local box (east and north
// ranges, metres); NaN when the box holds no cell with data.
double HighestHeight(const HeightGrid& grid, double east_min, double east_max, double north_min, double north_max);

// Where a ray from `origin` along `direction` (need not be unit) first goes
// below the surface, within `max_range_m` of the origin: marched in steps of
// half a cell, refined by bisection to a thousandth of a cell. nullopt when
// it does not meet the surface there (it leaves the grid, or crosses only holes).
std::optional<Eigen::Vector3d> FirstSurfaceHit(const HeightGrid& grid, const Eigen::Vector3d& origin,
                                               const Eigen::Vector3d& direction, double max_range_m);

// Whether `point` (on or just above the surface) is in sight of `eye`: the
// segment between them stays above the surface, with a tolerance of
// `tolerance_m`. `ceiling_m`: no cell along the way is higher (e.g.
// HighestHeight around them), so the march stops once the segment is above it.
bool InSight(const HeightGrid& grid, const Eigen::Vector3d& point, const Eigen::Vector3d& eye, double ceiling_m,
             double tolerance_m = 0.005);

}  // namespace seamap
