#include "core/terrain/line_of_sight.h"

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

TEST(LineOfSight, HeightIsTheGridsBilinearHeight) {
  const HeightGrid g = GridOf([](double e, double n) { return -30 + 0.2 * e + 0.1 * std::sin(3 * n); });
  const LineOfSight sight(g);
  for (const LocalXY p : {LocalXY{0.013, -0.27}, LocalXY{4.99, 4.99}, LocalXY{-5, -5}}) {
    double a = 0, b = 0;
    ASSERT_TRUE(sight.Height(p.east, p.north, &a));
    ASSERT_TRUE(g.Sample(p, &b));
    EXPECT_NEAR(a, b, 1e-9);
  }
  double h = 0;
  EXPECT_FALSE(sight.Height(5.1, 0, &h));
}

TEST(LineOfSight, ARidgeHidesTheGroundBehindIt) {
  // Flat at -30 with a 1 m high ridge along north at 1.0..1.2 m east.
  const HeightGrid g = GridOf([](double e, double) { return e > 1.0 && e < 1.2 ? -29.0 : -30.0; });
  const LineOfSight sight(g);
  const Eigen::Vector3d behind(1.5, 0, -30), in_front(0.7, 0, -30);
  const Eigen::Vector3d west_eye(0, 0.2, -28), east_eye(2.5, -0.3, -28);
  EXPECT_FALSE(sight.Clear(behind, west_eye));
  EXPECT_TRUE(sight.Clear(behind, east_eye));
  EXPECT_TRUE(sight.Clear(in_front, west_eye));
  EXPECT_FALSE(sight.Clear(in_front, east_eye));
  // Straight below the eye nothing hides; the ridge's top is seen from both.
  EXPECT_TRUE(sight.Clear({0, 0.2, -30}, west_eye));
  EXPECT_TRUE(sight.Clear({1.1, 0, -29}, west_eye));
  EXPECT_TRUE(sight.Clear({1.1, 0, -29}, east_eye));
  EXPECT_FALSE(sight.Clear({0, 0, -30}, {0, 0, -31}));  // an eye below the point sees nothing
}

TEST(LineOfSight, SkippingBlocksAgreesWithAPlainMarch) {
  // Rough relief: the block-skipping march against a half-cell march with
  // no skipping, over many lines of sight.
  const HeightGrid g = GridOf([](double e, double n) {
    return -30 + 0.3 * std::sin(2.1 * e) * std::cos(1.7 * n) + 0.15 * std::sin(7.3 * e + 4.1 * n);
  });
  const LineOfSight sight(g);
  cv::RNG rng(7);
  int hidden = 0, checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const double e = rng.uniform(-3.0, 3.0), n = rng.uniform(-3.0, 3.0);
    double up = 0;
    ASSERT_TRUE(g.Sample({e, n}, &up));
    const Eigen::Vector3d point(e, n, up);
    const Eigen::Vector3d eye(e + rng.uniform(-2.0, 2.0), n + rng.uniform(-2.0, 2.0), -29);
    const Eigen::Vector3d d = eye - point;
    const double length = std::hypot(d.x(), d.y());
    bool plain = true;
    for (double s = g.cell_m / 2; s < length && plain; s += g.cell_m / 2) {
      double h = 0;
      const Eigen::Vector3d q = point + d * (s / length);
      if (g.Sample({q.x(), q.y()}, &h) && h > q.z() + 0.005) plain = false;
    }
    ++checked;
    hidden += !plain;
    EXPECT_EQ(sight.Clear(point, eye), plain) << i;
  }
  EXPECT_GT(hidden, 50);  // the relief does hide some
  EXPECT_LT(hidden, checked - 50);
}

TEST(LineOfSight, HolesAreTransparent) {
  HeightGrid g = GridOf([](double e, double) { return e > 1.0 && e < 1.2 ? -29.0 : -30.0; });
  g.height_m(cv::Rect(100, 0, 30, 201)) = std::numeric_limits<float>::quiet_NaN();  // the ridge unknown
  const LineOfSight sight(g);
  EXPECT_TRUE(sight.Clear({1.6, 0, -30}, {0, 0, -28}));
}

}  // namespace
}  // namespace seamap
