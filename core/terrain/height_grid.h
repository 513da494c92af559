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
#include <algorithm>
#include <cmath>

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
  // The bilinear height at fractional cell indices, for the hot loops of ray
  // casting and occlusion: false outside the grid or when any of the four
  // cells around it is a hole (even one of weight 0: stricter than Sample).
  bool HeightAtCell(double row, double col, double* up_m) const {
    const int last_row = rows() - 1, last_col = cols() - 1;
    if (!(row >= 0 && col >= 0 && row <= last_row && col <= last_col)) return false;
    const int r0 = std::min(static_cast<int>(row), std::max(last_row - 1, 0));
    const int c0 = std::min(static_cast<int>(col), std::max(last_col - 1, 0));
    const int r1 = std::min(r0 + 1, last_row), c1 = std::min(c0 + 1, last_col);
    const double fr = row - r0, fc = col - c0;
    const float* a = height_m[r0];
    const float* b = height_m[r1];
    const double h = (1 - fr) * ((1 - fc) * a[c0] + fc * a[c1]) + fr * ((1 - fc) * b[c0] + fc * b[c1]);
    if (!std::isfinite(h)) return false;
    *up_m = h;
    return true;
  }
};

}  // namespace seamap
