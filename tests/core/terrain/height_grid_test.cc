#include "core/terrain/height_grid.h"

#include <cmath>

#include <gtest/gtest.h>

namespace seamap {
namespace {

HeightGrid Ramp() {
  HeightGrid g;
  g.east0_m = 10;
  g.north0_m = 20;
  g.cell_m = 0.5;
  g.height_m = cv::Mat1f(4, 5);
  g.sigma_m = cv::Mat1f(4, 5, 0.01f);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) g.height_m(r, c) = static_cast<float>(-30 + 0.1 * c + 0.2 * r);
  return g;
}

TEST(HeightGrid, SamplesBilinearlyInLocalMetres) {
  HeightGrid g = Ramp();
  double h = 0, s = 0;
  ASSERT_TRUE(g.Sample({10.25, 19.75}, &h, &s));  // half a cell east and south of (0, 0)
  EXPECT_NEAR(h, -30 + 0.05 + 0.1, 1e-6);
  EXPECT_NEAR(s, 0.01, 1e-7);
  ASSERT_TRUE(g.Sample(g.CellCentre(3, 4), &h));  // the last cell exactly
  EXPECT_NEAR(h, -30 + 0.4 + 0.6, 1e-6);
  EXPECT_FALSE(g.Sample({9.9, 20}, &h));   // west of the grid
  EXPECT_FALSE(g.Sample({10, 20.1}, &h));  // north of it
}

TEST(HeightGrid, AHoleIsNotInterpolatedAcross) {
  HeightGrid g = Ramp();
  g.height_m(1, 1) = NAN;
  double h = 0;
  EXPECT_FALSE(g.Sample({10.25, 19.75}, &h));  // touches (1, 1)
  EXPECT_TRUE(g.Sample(g.CellCentre(0, 0), &h));
  EXPECT_TRUE(g.Sample({11.5, 20}, &h));
}

}  // namespace
}  // namespace seamap
