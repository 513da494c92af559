#include "core/terrain/painting_surface.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace seamap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A 4 m square grid of `cell` m cells around the origin: heights from `up(east, north)`.
template <typename Up>
HeightGrid GridOf(double cell, Up up) {
  HeightGrid g;
  g.cell_m = cell;
  const int n = static_cast<int>(std::lround(4 / cell)) + 1;
  g.east0_m = -2;
  g.north0_m = 2;
  g.height_m = cv::Mat1f(n, n);
  g.sigma_m = cv::Mat1f(n, n, 0.005f);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(up(p.east, p.north));
    }
  return g;
}

double Relief(double e, double n) {
  return -35 + 0.15 * std::sin(2 * M_PI * e / 0.8) * std::cos(2 * M_PI * n / 1.1);
}

TEST(PaintingSurface, FinerCellsFollowTheReliefBetweenTheModelsCentres) {
  const HeightGrid model = GridOf(0.1, Relief);
  const HeightGrid fine = RefineHeightGrid(model, 3);
  ASSERT_EQ(fine.rows(), 3 * model.rows());
  EXPECT_NEAR(fine.cell_m, 0.1 / 3, 1e-12);
  EXPECT_TRUE(fine.sigma_m.empty());
  // The fine cells tile the model's: a model cell's centre is its middle fine cell's.
  const LocalXY centre = model.CellCentre(10, 12), middle = fine.CellCentre(31, 37);
  EXPECT_NEAR(centre.east, middle.east, 1e-9);
  EXPECT_NEAR(centre.north, middle.north, 1e-9);
  EXPECT_NEAR(fine.height_m(31, 37), model.height_m(10, 12), 1e-5);  // through every centre
  // Between the centres (inside, away from the edges) the cubic follows the
  // relief at least three times better than the model's bilinear surface.
  double cubic2 = 0, bilinear2 = 0;
  int n = 0;
  for (int r = 9; r < fine.rows() - 9; ++r)
    for (int c = 9; c < fine.cols() - 9; ++c) {
      const LocalXY p = fine.CellCentre(r, c);
      double coarse = 0;
      ASSERT_TRUE(model.Sample(p, &coarse));
      const double truth = Relief(p.east, p.north);
      cubic2 += std::pow(fine.height_m(r, c) - truth, 2);
      bilinear2 += std::pow(coarse - truth, 2);
      ++n;
    }
  const double cubic_rms = std::sqrt(cubic2 / n), bilinear_rms = std::sqrt(bilinear2 / n);
  EXPECT_LT(cubic_rms, bilinear_rms / 3) << cubic_rms << " vs " << bilinear_rms;
  EXPECT_GT(bilinear_rms, 0.002);  // the test means something: bilinear misses mm
}

TEST(PaintingSurface, HolesAmongTheTapsFallBackToBilinearOrStayHoles) {
  HeightGrid model = GridOf(0.1, [](double e, double) { return -30 + 0.2 * e; });
  model.height_m(20, 20) = kNaN;
  const HeightGrid fine = RefineHeightGrid(model, 2);
  // Next to the hole but with its 2x2 known: bilinear (exact on a plane).
  for (int r = 36; r < 46; ++r)
    for (int c = 36; c < 46; ++c) {
      const LocalXY p = fine.CellCentre(r, c);
      if (std::isfinite(fine.height_m(r, c))) {
        EXPECT_NEAR(fine.height_m(r, c), -30 + 0.2 * p.east, 1e-5) << r << "," << c;
      } else {  // only where the hole is one of the 4 cells around it
        double row = 0, col = 0;
        model.CellOf(p, &row, &col);
        EXPECT_LT(std::fabs(row - 20), 1.0) << r << "," << c;
        EXPECT_LT(std::fabs(col - 20), 1.0) << r << "," << c;
      }
    }
}

TEST(PaintingSurface, HolesAreContinuedFromTheModelWithinReach) {
  // A sloping seabed whose model ends at east 0 (the swath's edge).
  const auto slope = [](double e, double) { return -30 + 0.3 * e; };
  HeightGrid model = GridOf(0.1, slope);
  for (int r = 0; r < model.rows(); ++r)
    for (int c = 0; c < model.cols(); ++c)
      if (model.CellCentre(r, c).east > 0.05) model.height_m(r, c) = model.sigma_m(r, c) = kNaN;
  // Straight on (slope_share 1), a plane continues exactly, and only within reach.
  HeightGrid straight = model;
  straight.height_m = model.height_m.clone();
  straight.sigma_m = model.sigma_m.clone();
  const long filled = ExtendHeightGrid(0.3, 1.0, &straight);
  EXPECT_EQ(filled, 3L * model.rows());
  for (int r = 0; r < model.rows(); ++r)
    for (int c = 0; c < model.cols(); ++c) {
      const double e = model.CellCentre(r, c).east;
      if (e < 0.35) {
        EXPECT_NEAR(straight.height_m(r, c), slope(e, 0), 1e-4) << r << "," << c;
      } else {
        EXPECT_TRUE(std::isnan(straight.height_m(r, c))) << "beyond reach: the plane stands in";
      }
      if (e > 0.05 && e < 0.35) {
        EXPECT_TRUE(std::isnan(straight.sigma_m(r, c))) << "nothing measured it";
      }
    }
  // Level (slope_share 0): the rim's height carried on.
  HeightGrid level = model;
  level.height_m = model.height_m.clone();
  level.sigma_m = model.sigma_m.clone();
  ExtendHeightGrid(0.3, 0.0, &level);
  EXPECT_NEAR(level.height_m(20, model.cols() / 2 + 3), slope(0, 0), 1e-4);
  // The painting copy: continued by half the slope, refined; the model untouched.
  PaintingSurfaceOptions options;
  options.refine = 2;
  PaintingSurfaceReport report;
  const HeightGrid painted = PaintingSurface(model, options, &report);
  EXPECT_EQ(report.cells_extended, 5L * model.rows());
  EXPECT_TRUE(std::isnan(model.height_m(20, model.cols() / 2 + 1)));
  double up = 0;
  ASSERT_TRUE(painted.Sample({0.2, 0}, &up));
  EXPECT_GT(up, slope(0, 0));           // rising on with the slope ...
  EXPECT_LT(up, slope(0.2, 0) + 1e-6);  // ... but not past a straight continuation
}

}  // namespace
}  // namespace seamap
