#include "core/terrain/height_datum.h"

#include <cmath>

namespace seamap {

HeightDatum UserDatum(const HeightGrid& grid) {
  if (grid.has_depth_datum) return {"sea_surface", 0.0};
  double sum = 0;
  long count = 0;
  for (int r = 0; r < grid.rows(); ++r) {
    const float* row = grid.height_m[r];
    for (int c = 0; c < grid.cols(); ++c)
      if (std::isfinite(row[c])) {
        sum += row[c];
        ++count;
      }
  }
  return {"mean_seabed", count > 0 ? -sum / count : 0.0};
}

}  // namespace seamap
