#include "core/terrain/surface_ray.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace seamap {
namespace {

// A 10 m square grid at 5 cm around the origin: heights from `up(east, north)`.
template <typename Up>
HeightGrid GridOf(Up up) {
  HeightGrid g;
  g.cell_m = 0.05;
  g.east0_m = -5;
  g.north0_m = 5;
  g.height_m = cv::Mat1f(201, 201);
  g.sigma_m = cv::Mat1f(201, 201, 0.01f);
  for (int r = 0; r < g.rows(); ++r)
    for (int c = 0; c < g.cols(); ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(up(p.east, p.north));
    }
  return g;
}

TEST(SurfaceRay, ARayMeetsASlopeWhereTheGeometrySays) {
  // A plane rising 0.2 m per metre east, -30 m at the origin.
  const HeightGrid g = GridOf([](double e, double) { return -30 + 0.2 * e; });
  const Eigen::Vector3d eye(0, 0, -28), down_east(0.5, 0.3, -1);
  const auto hit = FirstSurfaceHit(g, eye, down_east, 10);
  ASSERT_TRUE(hit);
  // eye + t d on z = -30 + 0.2 x: -28 - t = -30 + 0.1 t -> t = 2 / 1.1.
  const double t = 2 / 1.1;
  EXPECT_NEAR(hit->x(), 0.5 * t, 1e-3);
  EXPECT_NEAR(hit->y(), 0.3 * t, 1e-3);
  EXPECT_NEAR(hit->z(), -28 - t, 1e-3);
  EXPECT_FALSE(FirstSurfaceHit(g, eye, Eigen::Vector3d(0, 0, 1), 10));  // upwards
  EXPECT_FALSE(FirstSurfaceHit(g, eye, down_east, 1.0));                // not that far
}

TEST(SurfaceRay, HolesAreTransparent) {
  HeightGrid g = GridOf([](double, double) { return -30.0; });
  g.height_m(cv::Rect(90, 90, 21, 21)) = std::numeric_limits<float>::quiet_NaN();  // a hole under the origin
  EXPECT_FALSE(FirstSurfaceHit(g, {0, 0, -28}, {0, 0, -1}, 10));
  const auto hit = FirstSurfaceHit(g, {0, 0, -28}, {1, 0, -1}, 10);  // beyond the hole's edge at 0.5 m
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->z(), -30, 1e-3);
}

TEST(SurfaceRay, AWallHidesTheGroundBehindIt) {
  // Flat at -30 with a 1 m high ridge along north at 1.0..1.2 m east.
  const HeightGrid g = GridOf([](double e, double) { return e > 1.0 && e < 1.2 ? -29.0 : -30.0; });
  const double ceiling = HighestHeight(g, -5, 5, -5, 5);
  EXPECT_NEAR(ceiling, -29, 1e-6);
  const Eigen::Vector3d behind(1.5, 0, -30), in_front(0.7, 0, -30);
  const Eigen::Vector3d west_eye(0, 0, -28), east_eye(2.5, 0, -28);
  EXPECT_FALSE(InSight(g, behind, west_eye, ceiling));
  EXPECT_TRUE(InSight(g, behind, east_eye, ceiling));
  EXPECT_TRUE(InSight(g, in_front, west_eye, ceiling));
  EXPECT_FALSE(InSight(g, in_front, east_eye, ceiling));
  // Straight below the eye nothing hides; the ridge's top is seen from both.
  EXPECT_TRUE(InSight(g, {0, 0, -30}, west_eye, ceiling));
  EXPECT_TRUE(InSight(g, {1.1, 0, -29}, west_eye, ceiling));
  EXPECT_TRUE(InSight(g, {1.1, 0, -29}, east_eye, ceiling));
}

TEST(SurfaceRay, HighestHeightSkipsHolesAndIsNaNOverHolesOnly) {
  HeightGrid g = GridOf([](double e, double) { return -30 + 0.1 * e; });
  EXPECT_NEAR(HighestHeight(g, -1, 1, -1, 1), -29.9, 1e-5);
  g.height_m(cv::Rect(0, 0, 201, 201)) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isnan(HighestHeight(g, -1, 1, -1, 1)));
}

}  // namespace
}  // namespace seamap
