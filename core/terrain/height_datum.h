#pragma once
// The heights a user is shown (export --dem, /api/terrain, the relief
// legend): relative to the sea surface where the navigation had depth_m (the
// stored heights as they are), else relative to the survey's mean seabed
// (the stored heights are relative to an assumed vehicle depth of 0, which
// means nothing to a user).
#include <string>

#include "core/terrain/height_grid.h"

namespace seamap {

struct HeightDatum {
  std::string name;     // "sea_surface" or "mean_seabed"
  double offset_m = 0;  // user height = stored height + offset_m
};

// For a grid without a depth datum and without a single finite height, the
// offset is 0.
HeightDatum UserDatum(const HeightGrid& grid);

}  // namespace seamap
