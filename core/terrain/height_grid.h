#pragma once
// The seabed's shape: a regular grid of heights in the mission's local frame
// (core/geo/local_frame.h), with a per-cell uncertainty and holes. It is the
// one height model of SeaMap: the simulator's truth, what `build --terrain`
// fits to the photos, what a true orthophoto is projected onto, what
// `export --dem` writes and `/api/terrain` answers.
//
// Vertical datum: metres UP. With navigation depth (depth_m), 0 is the sea
// surface, so a seabed 35 m down is -35; a camera's height is -depth_m.
// Without depth, the vehicle is taken at a constant depth of 0, so heights
// are relative to it (see has_depth_datum).
#include <opencv2/core.hpp>

#include "core/geo/local_frame.h"

namespace seamap {

struct HeightGrid {
  // Centre of cell (row 0, col 0) in local metres; rows run SOUTH (north
  // decreases with the row), columns run east, as an image of the seabed.
  double east0_m = 0, north0_m = 0;
  double cell_m = 0.05;
  cv::Mat1f height_m;           // metres up; NaN: a hole (no data)
  cv::Mat1f sigma_m;            // 1-sigma of height_m, same size; NaN where height_m is
  bool has_depth_datum = true;  // heights are relative to the sea surface

  int rows() const { return height_m.rows; }
  int cols() const { return height_m.cols; }
  bool empty() const { return height_m.empty(); }
  // Local metres of a cell's centre, and back (fractional cell indices).
  LocalXY CellCentre(int row, int col) const { return {east0_m + col * cell_m, north0_m - row * cell_m}; }
  void CellOf(LocalXY p, double* row, double* col) const {
    *col = (p.east - east0_m) / cell_m;
    *row = (north0_m - p.north) / cell_m;
  }
  // Bilinear height (and sigma) at a local point; false outside the grid or
  // where any of the four cells around it is a hole.
  bool Sample(LocalXY p, double* height_m_out, double* sigma_m_out = nullptr) const;
};

}  // namespace seamap
