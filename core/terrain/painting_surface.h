#pragma once
// The height model as a true orthophoto paints onto it (build --terrain,
// --terrain-file): the stored model (the DEM, /api/terrain) is left as it
// is; the frames are painted onto a copy prepared in two ways.
//
// 1. Holes near known cells are filled by continuing the surface. The fitted
//    model leaves a hole wherever its points do not surround a cell (the
//    swath's edges) and beyond the footprints, yet a frame paints up to its
//    image edges there, and the plane at its altitude, the only other stand-in,
//    is off by the relief itself. Ring by ring from the known cells, each new
//    cell takes the mean of its known neighbours' heights, each continued by
//    `slope_share` of the slope behind it (0: level, 1: straight on).
// 2. Finer cells, by cubic convolution (Keys, a = -0.5: it passes through
//    every cell centre and follows the curvature between them). The painting
//    surface is bilinear between cells, so on a model of 0.1 m cells a bump
//    between centres is cut flat: on the survey that alone moved the
//    texture's p90 from 0.89 px (cells three times finer) to 1.18 px.
#include "core/terrain/height_grid.h"

namespace seamap {

struct PaintingSurfaceOptions {
  double reach_m = 0.5;      // holes further from any known cell stay holes (the frame's plane stands in)
  double slope_share = 0.5;  // how much of the rim's slope the continued surface keeps
  int refine = 1;            // cells per model cell along each axis (1: as the model)
};

struct PaintingSurfaceReport {
  long cells_extended = 0;  // model cells filled by continuing the surface
};

// The painting copy of `model`; its sigma_m is left empty (nothing paints with it).
HeightGrid PaintingSurface(const HeightGrid& model, const PaintingSurfaceOptions& options,
                           PaintingSurfaceReport* report = nullptr);

// Step 1 alone, in place: fills holes within reach_m of a known cell, their sigma NaN; returns how many.
long ExtendHeightGrid(double reach_m, double slope_share, HeightGrid* grid);

// Step 2 alone: `factor` cells per cell, covering the same extent, by cubic
// convolution where the 4x4 cells around a point are known, bilinear where
// only the 2x2 are, else a hole.
HeightGrid RefineHeightGrid(const HeightGrid& grid, int factor);

}  // namespace seamap
