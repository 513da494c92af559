#pragma once
// The height model drawn for a person: a colour relief (a fixed ramp from
// the lowest to the highest height) shaded by a hillshade (light from the
// north-west, 45 degrees up), cell for cell. The console's relief layer is
// made of it (core/mission/relief_layer.h); its legend repeats the ramp
// (web/js/relief.js keeps the same stops).
#include <array>

#include <opencv2/core.hpp>

#include "core/terrain/height_grid.h"

namespace seamap {

struct ReliefStyle {
  double low_m = 0, high_m = 1;  // stored heights at the ramp's ends (clamped beyond)
  double sun_azimuth_deg = 315;  // clockwise from north: the light comes from the north-west
  double sun_elevation_deg = 45;
  double z_factor = 1;  // vertical exaggeration of the hillshade
  // The hillshade's slopes from heights smoothed by a Gaussian of this many
  // cells (holes left out): a height model's cell-scale noise, and the facets
  // of an interpolated one, would otherwise speckle the shading.
  double smooth_cells = 1;
};

// The ramp's stops (RGB), evenly spaced from low (deep blue) to high (brown).
constexpr int kReliefRampStops = 6;
extern const std::array<std::array<uint8_t, 3>, kReliefRampStops> kReliefRampRgb;

// The grid's lowest and highest finite heights as the ramp's ends (0..1 for
// a grid without any; a flat grid gets a 1 cm span around its height).
ReliefStyle ReliefStyleFor(const HeightGrid& grid);

// The ramp's colour (BGR) at t in [0, 1] (clamped).
cv::Vec3b RampColour(double t);

// One BGRA pixel per cell: ramp colour (of the cell's height) times the
// hillshade (0.4 + 0.6 * cos of the angle between the smoothed surface's
// normal and the light); holes are
// transparent (alpha 0), every other cell opaque.
cv::Mat4b ShadeRelief(const HeightGrid& grid, const ReliefStyle& style);

}  // namespace seamap
