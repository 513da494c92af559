#include "core/terrain/relief_shading.h"

#include <cmath>

#include <gtest/gtest.h>

namespace seamap {
namespace {

// A plane rising towards `uphill` (east, north) by `slope` m/m, 0.1 m cells.
HeightGrid Plane(double slope_e, double slope_n) {
  HeightGrid g;
  g.cell_m = 0.1;
  g.height_m = cv::Mat1f(9, 9);
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(-20 + slope_e * p.east + slope_n * p.north);
    }
  g.sigma_m = cv::Mat1f(9, 9, 0.01f);
  return g;
}

int Brightness(const cv::Vec4b& p) {
  return p[0] + p[1] + p[2];
}

TEST(ReliefShading, RampRunsFromDeepBlueToBrownAndClamps) {
  EXPECT_EQ(RampColour(0), cv::Vec3b(140, 49, 33));  // BGR of the first stop
  EXPECT_EQ(RampColour(1), cv::Vec3b(26, 97, 166));
  EXPECT_EQ(RampColour(-3), RampColour(0));
  EXPECT_EQ(RampColour(7), RampColour(1));
  EXPECT_EQ(RampColour(0.2), cv::Vec3b(182, 123, 44));  // the second stop exactly
}

TEST(ReliefShading, StyleSpansTheGridsHeightsIgnoringHoles) {
  HeightGrid g = Plane(0.5, 0);
  g.height_m(0, 8) = NAN;
  const ReliefStyle s = ReliefStyleFor(g);
  EXPECT_NEAR(s.low_m, -20, 1e-5);
  EXPECT_NEAR(s.high_m, -20 + 0.5 * 0.8, 1e-5);
  HeightGrid flat = Plane(0, 0);
  const ReliefStyle f = ReliefStyleFor(flat);
  EXPECT_NEAR(f.high_m - f.low_m, 0.01, 1e-9);
}

TEST(ReliefShading, SlopesFacingTheLightAreBrighterAndHolesTransparent) {
  // Rising to the south-east faces the north-west sun; rising to the north-west faces away.
  HeightGrid towards = Plane(0.7, -0.7), away = Plane(-0.7, 0.7), flat = Plane(0, 0);
  ReliefStyle style;
  style.low_m = -100;  // one colour for all three
  style.high_m = 100;
  const cv::Mat4b lit = ShadeRelief(towards, style), dark = ShadeRelief(away, style), level = ShadeRelief(flat, style);
  EXPECT_GT(Brightness(lit(4, 4)), Brightness(level(4, 4)) + 30);
  EXPECT_LT(Brightness(dark(4, 4)), Brightness(level(4, 4)) - 30);
  EXPECT_EQ(lit(4, 4)[3], 255);
  towards.height_m(2, 3) = NAN;
  const cv::Mat4b holed = ShadeRelief(towards, style);
  EXPECT_EQ(holed(2, 3)[3], 0);
  // Next to the hole the slope is still the plane's: the smoothing leaves the hole out.
  EXPECT_EQ(holed(2, 4)[3], 255);
  EXPECT_NEAR(Brightness(holed(2, 4)), Brightness(lit(2, 4)), 6);
}

TEST(ReliefShading, CellScaleNoiseDoesNotSpeckleTheShading) {
  HeightGrid noisy = Plane(0, 0);
  cv::Mat1f noise(noisy.height_m.size());
  cv::randn(noise, 0, 0.01);  // 1 cm noise on 10 cm cells: slopes of +-0.14 cell to cell
  noisy.height_m += noise;
  ReliefStyle style;
  style.low_m = -100;
  style.high_m = 100;
  ReliefStyle raw = style;
  raw.smooth_cells = 0;
  const auto spread = [](const cv::Mat4b& shaded) {
    int lo = 1000, hi = 0;
    for (int r = 2; r < 7; ++r)
      for (int c = 2; c < 7; ++c)
        lo = std::min(lo, Brightness(shaded(r, c))), hi = std::max(hi, Brightness(shaded(r, c)));
    return hi - lo;
  };
  EXPECT_LT(spread(ShadeRelief(noisy, style)), spread(ShadeRelief(noisy, raw)) / 2);
}

TEST(ReliefShading, HeightPicksTheRampColour) {
  HeightGrid g = Plane(0, 0);
  g.height_m(0, 0) = -30;
  g.height_m(8, 8) = -10;
  ReliefStyle style = ReliefStyleFor(g);
  style.sun_elevation_deg = 90;  // a flat cell lit from overhead: gain 1
  const cv::Mat4b shaded = ShadeRelief(g, style);
  EXPECT_EQ(shaded(4, 4)[0], RampColour(0.5)[0]);
  EXPECT_EQ(shaded(4, 4)[2], RampColour(0.5)[2]);
}

}  // namespace
}  // namespace seamap
