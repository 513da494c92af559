#include "core/terrain/height_grid_ray.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/terrain/dvl_altitude.h"

namespace seamap {
namespace {

// A grid of `rows` x `cols` cells of 2 cm from (0, 0) running south-east, filled by height(east, north).
template <typename F>
HeightGrid Grid(int rows, int cols, F height) {
  HeightGrid g;
  g.cell_m = 0.02;
  g.east0_m = -cols * g.cell_m / 2;
  g.north0_m = rows * g.cell_m / 2;
  g.height_m.create(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(height(p.east, p.north));
    }
  g.sigma_m = cv::Mat1f(rows, cols, 0.f);
  return g;
}

TEST(HeightGridRayCaster, HitsAFlatSeabedWhereThePlaneDoes) {
  const HeightGridRayCaster caster(Grid(200, 200, [](double, double) { return -35.0; }));
  const Eigen::Vector3d origin(0.1, -0.2, -33);
  for (const Eigen::Vector3d& d :
       {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0.3, -0.4, -1), Eigen::Vector3d(-0.5, 0.2, -0.8)}) {
    double t = 0;
    ASSERT_TRUE(caster.Cast(origin, d, &t));
    EXPECT_NEAR(t, 2 / -d.z(), 2e-5);
  }
  double t = 0;
  EXPECT_FALSE(caster.Cast(origin, {0, 0, 1}, &t));        // up: no seabed there
  EXPECT_FALSE(caster.Cast(origin, {5, 0, -1}, &t));       // leaves the grid before the seabed
  EXPECT_FALSE(caster.Cast({0, 0, -36}, {0, 0, -1}, &t));  // starts under the seabed
}

TEST(HeightGridRayCaster, StopsOnTheFirstHitOfABump) {
  // A 0.5 m high gaussian bump at east 0.5 on a seabed at -35.
  const auto height = [](double e, double n) { return -35 + 0.5 * std::exp(-((e - 0.5) * (e - 0.5) + n * n) / 0.02); };
  const HeightGridRayCaster caster(Grid(300, 300, height));
  // From 2 m above the seabed at east -1.0 towards a plane point at east 2.0: the ray passes
  // the bump's top at a height of -35 + 2 * (1 - 1.5 / 3) = -34, clear, ...
  double t = 0;
  const Eigen::Vector3d origin(-1.0, 0, -33);
  ASSERT_TRUE(caster.Cast(origin, {3.0, 0, -2}, &t));
  EXPECT_NEAR(t, 1.0, 1e-4);
  // ... but a ray towards east 0.8 passes east 0.5 at -34.67, below the bump's top -34.5: it stops on the bump's near
  // side.
  ASSERT_TRUE(caster.Cast(origin, {1.8, 0, -2}, &t));
  const Eigen::Vector3d hit = origin + t * Eigen::Vector3d(1.8, 0, -2);
  EXPECT_LT(hit.x(), 0.5);
  EXPECT_GT(hit.z(), -34.9);
  EXPECT_NEAR(hit.z(), height(hit.x(), hit.y()), 2e-3);  // on the (bilinear) surface
}

TEST(DvlAltitude, IsTheVerticalDistanceOverAFlatSeabedAtAnyAttitude) {
  const HeightGridRayCaster caster(Grid(400, 400, [](double, double) { return -35.0; }));
  EXPECT_NEAR(DvlAltitude(caster, {0.1, 0.2}, -33.0, 0, 0, 0), 2.0, 1e-4);
  EXPECT_NEAR(DvlAltitude(caster, {0.1, 0.2}, -33.0, 37, 5, -4), 2.0, 1e-4);
}

TEST(DvlAltitude, AveragesTheSeabedUnderItsFourBeams) {
  // A seabed sloping up to the east (10 %): the beams east and west see it
  // higher and lower by as much, so the mean is the range below.
  const HeightGridRayCaster slope(Grid(400, 400, [](double e, double) { return -35.0 + 0.1 * e; }));
  const double altitude = DvlAltitude(slope, {0, 0}, -33.0, 0, 0, 0);
  EXPECT_NEAR(altitude, 2.0, 0.005);
  // A bump right below the vehicle but between the beams is not seen; the point-below range would be 1.5.
  const HeightGridRayCaster bump(
      Grid(400, 400, [](double e, double n) { return -35.0 + 0.5 * std::exp(-(e * e + n * n) / 0.01); }));
  EXPECT_NEAR(DvlAltitude(bump, {0, 0}, -33.0, 0, 0, 0), 2.0, 1e-3);
}

}  // namespace
}  // namespace seamap
