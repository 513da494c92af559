// The height model takes seabed points from elsewhere (a stereo rig's pairs,
// build --terrain-points) with the photos' own tracks.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/trajectory/seabed_terrain.h"
#include "tests/core/trajectory/synthetic_seabed.h"

namespace seamap {
namespace {

using testing_seabed::Lawnmower;
using testing_seabed::Relief;
using testing_seabed::Scene;

// RMS of the grid against the relief over its cells, mean offset removed.
double RmsAgainst(const HeightGrid& grid, const Relief& relief) {
  std::vector<double> error;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c)
      if (std::isfinite(grid.height_m(r, c))) {
        const LocalXY p = grid.CellCentre(r, c);
        error.push_back(grid.height_m(r, c) - relief.Up(p.east, p.north));
      }
  double mean = 0, sum = 0;
  for (double e : error) mean += e / error.size();
  for (double e : error) sum += (e - mean) * (e - mean);
  return std::sqrt(sum / error.size());
}

TEST(SeabedTerrainStereo, ExtraPointsAreFittedWithTheTracks) {
  const Relief relief(0.3, 23);
  Scene scene;
  scene.poses = Lawnmower(relief, 3, 5.0, 0.9, 0.15);
  scene.ScatterOnRelief(relief, -2, 3.8, -2, 7, 60);  // sparse texture: few tracks
  const auto features = [&](int i) { return scene.FeaturesOf(i); };
  TerrainReport alone;
  const HeightGrid photos = EstimateSeabedTerrainFromFeatures(scene.poses, scene.camera, features, {}, &alone);
  ASSERT_FALSE(photos.empty());

  // A stereo rig's points: every 4 cm over the swath, 3 mm of noise in height.
  TerrainOptions options;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.003);
  for (double e = -0.6; e <= 2.4; e += 0.04)
    for (double n = -0.5; n <= 5.5; n += 0.04) {
      SeabedPoint p;
      p.east_north_up_m = {e, n, relief.Up(e, n) + noise(rng)};
      p.sigma_up_m = 0.003;
      p.views = 2;
      options.extra_points.push_back(p);
    }
  TerrainReport both;
  const HeightGrid grid = EstimateSeabedTerrainFromFeatures(scene.poses, scene.camera, features, options, &both);
  ASSERT_FALSE(grid.empty());
  EXPECT_EQ(both.fit.points, alone.fit.points + static_cast<long>(options.extra_points.size()));
  const double rms_photos = RmsAgainst(photos, relief), rms_both = RmsAgainst(grid, relief);
  EXPECT_LT(rms_both, 0.010) << "photos alone " << rms_photos;
  EXPECT_LT(rms_both, 0.8 * rms_photos);
}

}  // namespace
}  // namespace seamap
