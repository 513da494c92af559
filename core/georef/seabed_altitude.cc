#include "core/georef/seabed_altitude.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace seamap {
namespace {

// Cells of radius_m on a side: the points within the radius of any position
// lie in its cell's 3x3 neighbourhood.
struct Grid {
  double cell_m;
  std::unordered_map<long long, std::vector<int>> cells;
  long long Key(long long ix, long long iy) const { return (ix << 32) ^ (iy & 0xffffffffLL); }
  long long Index(double v) const { return static_cast<long long>(std::floor(v / cell_m)); }
};

}  // namespace

std::vector<std::optional<double>> AltitudeFromCloud(const std::vector<Eigen::Vector3d>& keyframes,
                                                     const std::vector<Eigen::Vector3d>& cloud,
                                                     const SeabedAltitudeOptions& options) {
  Grid grid{std::max(options.radius_m, 1e-3), {}};
  for (size_t i = 0; i < cloud.size(); ++i)
    grid.cells[grid.Key(grid.Index(cloud[i].x()), grid.Index(cloud[i].y()))].push_back(static_cast<int>(i));
  const double r2 = options.radius_m * options.radius_m;
  std::vector<std::optional<double>> out(keyframes.size());
  std::vector<double> ups;
  for (size_t k = 0; k < keyframes.size(); ++k) {
    const Eigen::Vector3d& p = keyframes[k];
    const long long cx = grid.Index(p.x()), cy = grid.Index(p.y());
    ups.clear();
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy) {
        auto it = grid.cells.find(grid.Key(cx + dx, cy + dy));
        if (it == grid.cells.end()) continue;
        for (int i : it->second)
          if ((cloud[i].head<2>() - p.head<2>()).squaredNorm() <= r2) ups.push_back(cloud[i].z());
      }
    if (static_cast<int>(ups.size()) < options.min_points) continue;
    std::nth_element(ups.begin(), ups.begin() + ups.size() / 2, ups.end());
    const double altitude = p.z() - ups[ups.size() / 2];
    if (altitude > 0) out[k] = altitude;
  }
  return out;
}

}  // namespace seamap
