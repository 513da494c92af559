#include "core/terrain/height_fit.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

// Smooth relief, wavelengths 0.7-3 m, about 0.3 m rms, around -12 m.
double TrueUp(double east, double north) {
  return -12 + 0.25 * std::sin(2.1 * east + 0.4) + 0.2 * std::sin(1.3 * north + 1.9 * east) +
         0.08 * std::sin(7.5 * north + 1.1) + 0.05 * std::sin(6 * east - 5 * north);
}

SeabedPoints NoisyPoints(double e0, double e1, double n0, double n1, double per_m2, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ue(e0, e1), un(n0, n1), us(0.002, 0.008);
  std::normal_distribution<double> noise(0, 1);
  SeabedPoints points;
  const int n = static_cast<int>(per_m2 * (e1 - e0) * (n1 - n0));
  for (int k = 0; k < n; ++k) {
    SeabedPoint p;
    const double e = ue(rng), no = un(rng), sigma = us(rng);
    p.east_north_up_m = {e, no, TrueUp(e, no) + sigma * noise(rng)};
    p.sigma_up_m = sigma;
    p.views = 3;
    points.push_back(p);
  }
  return points;
}

std::array<LocalXY, 4> Rectangle(double e0, double e1, double n0, double n1) {
  return {LocalXY{e0, n1}, LocalXY{e1, n1}, LocalXY{e1, n0}, LocalXY{e0, n0}};
}

struct Accuracy {
  double rms_m = 0, coverage = 0, within1 = 0, within2 = 0;
};

// Against the truth over the cells inside [e0, e1] x [n0, n1], after removing the mean offset.
Accuracy Measure(const HeightGrid& grid, double e0, double e1, double n0, double n1) {
  std::vector<double> error, sigma;
  long cells = 0;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      const LocalXY p = grid.CellCentre(r, c);
      if (p.east < e0 || p.east > e1 || p.north < n0 || p.north > n1) continue;
      ++cells;
      if (!std::isfinite(grid.height_m(r, c))) continue;
      error.push_back(grid.height_m(r, c) - TrueUp(p.east, p.north));
      sigma.push_back(grid.sigma_m(r, c));
    }
  Accuracy a;
  if (error.empty()) return a;
  double mean = 0;
  for (double e : error) mean += e / error.size();
  double sum = 0;
  long in1 = 0, in2 = 0;
  for (size_t k = 0; k < error.size(); ++k) {
    const double e = error[k] - mean;
    sum += e * e;
    in1 += std::fabs(e) <= sigma[k];
    in2 += std::fabs(e) <= 2 * sigma[k];
  }
  a.rms_m = std::sqrt(sum / error.size());
  a.coverage = static_cast<double>(error.size()) / cells;
  a.within1 = static_cast<double>(in1) / error.size();
  a.within2 = static_cast<double>(in2) / error.size();
  return a;
}

TEST(HeightFit, FitsReliefWithinMillimetresAndAnHonestSigma) {
  const SeabedPoints points = NoisyPoints(0, 4, 0, 3, 1500, 1);
  HeightFitOptions options;
  options.gsd_m = 0.004;
  HeightFitReport report;
  const HeightGrid grid = FitHeightGrid(points, {Rectangle(0, 4, 0, 3)}, true, options, &report);
  ASSERT_FALSE(grid.empty());
  EXPECT_TRUE(grid.has_depth_datum);
  EXPECT_GE(report.cell_m, 8 * options.gsd_m);
  EXPECT_LE(report.cell_m, 0.1);
  const Accuracy a = Measure(grid, 0.1, 3.9, 0.1, 2.9);
  EXPECT_LT(a.rms_m, 0.008) << "cell " << report.cell_m;
  EXPECT_GT(a.coverage, 0.99);
  // Calibrated: about 68 % within 1 sigma and 95 % within 2.
  EXPECT_GT(a.within1, 0.55) << a.within2;
  EXPECT_LT(a.within1, 0.85);
  EXPECT_GT(a.within2, 0.88);
  EXPECT_GT(report.cells_swath, 0.9 * grid.rows() * grid.cols());
  EXPECT_LT(report.cells_holes, 0.03 * report.cells_swath) << "only along the swath's edge";
}

TEST(HeightFit, RejectsFishParticlesAndAClusterOfOutliers) {
  SeabedPoints points = NoisyPoints(0, 4, 0, 3, 1500, 2);
  const size_t good = points.size();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ue(0, 4), un(0, 3), lift(0.1, 0.8), us(0.003, 0.03);
  for (size_t k = 0; k < good / 10; ++k) {  // 10 % scattered: fish and particles above, false matches below
    SeabedPoint p;
    const double e = ue(rng), n = un(rng);
    p.east_north_up_m = {e, n, TrueUp(e, n) + (k % 3 == 0 ? -1 : 1) * lift(rng)};
    p.sigma_up_m = us(rng);
    points.push_back(p);
  }
  for (int k = 0; k < 10; ++k) {  // a school of fish: 10 points 0.3 m up within 10 cm (15 seabed points there)
    SeabedPoint p;
    const double e = 2 + 0.1 * ue(rng) / 4, n = 1.5 + 0.1 * un(rng) / 3;
    p.east_north_up_m = {e, n, TrueUp(e, n) + 0.3};
    p.sigma_up_m = 0.01;
    points.push_back(p);
  }
  HeightFitOptions options;
  options.gsd_m = 0.004;
  HeightFitReport report;
  const HeightGrid grid = FitHeightGrid(points, {Rectangle(0, 4, 0, 3)}, true, options, &report);
  EXPECT_GT(report.points_rejected, static_cast<long>(0.8 * (good / 10)));
  const Accuracy a = Measure(grid, 0.1, 3.9, 0.1, 2.9);
  EXPECT_LT(a.rms_m, 0.012);
  EXPECT_GT(a.coverage, 0.99);
  double h = 0;
  ASSERT_TRUE(grid.Sample({2.05, 1.55}, &h));
  EXPECT_NEAR(h, TrueUp(2.05, 1.55), 0.03) << "the school of fish is not the seabed";
}

TEST(HeightFit, FillsSmallHolesAndLeavesLargeOnesAndTheOutsideEmpty) {
  SeabedPoints all = NoisyPoints(0, 6, 0, 4, 1200, 3);
  SeabedPoints points;
  for (const SeabedPoint& p : all) {
    const double e = p.east_north_up_m.x(), n = p.east_north_up_m.y();
    if (std::hypot(e - 1.5, n - 2) < 0.12) continue;  // a small hole
    if (std::hypot(e - 4, n - 2) < 0.8) continue;     // a large one
    points.push_back(p);
  }
  HeightFitOptions options;
  options.cell_m = 0.05;
  options.max_fill_m = 0.4;
  HeightFitReport report;
  // The swath: the rectangle less its north-east corner.
  const std::vector<std::array<LocalXY, 4>> swath = {Rectangle(0, 6, 0, 3), Rectangle(0, 3, 3, 4)};
  const HeightGrid grid = FitHeightGrid(points, swath, false, options, &report);
  EXPECT_FALSE(grid.has_depth_datum);
  EXPECT_DOUBLE_EQ(report.cell_m, 0.05);
  EXPECT_GT(report.cells_filled, 5);
  double h = 0, s = 0, s_rim = 0, h_rim = 0;
  ASSERT_TRUE(grid.Sample({1.5, 2}, &h, &s)) << "a small hole is filled";
  EXPECT_NEAR(h, TrueUp(1.5, 2), std::min(0.03, 3 * s)) << "sigma " << s;
  ASSERT_TRUE(grid.Sample({1.5, 2.5}, &h_rim, &s_rim));
  EXPECT_GT(s, s_rim) << "an interpolated cell is less certain";
  EXPECT_FALSE(grid.Sample({4, 2}, &h)) << "a large hole stays a hole";
  EXPECT_FALSE(grid.Sample({5, 3.7}, &h)) << "outside the swath";
  EXPECT_GT(report.cells_holes, 500);
}

TEST(HeightFit, NoPointsNoGridAndOptionsNameTheBadOne) {
  EXPECT_TRUE(FitHeightGrid({}, {}, true, HeightFitOptions()).empty());
  HeightFitOptions o;
  o.cell_m = -1;
  try {
    o.Check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--dem-cell");
  }
  o = HeightFitOptions();
  o.cell_m = 1e-6;
  EXPECT_THROW(FitHeightGrid(NoisyPoints(0, 100, 0, 100, 0.1, 4), {}, true, o), InputError) << "a grid too large";
}

}  // namespace
}  // namespace seamap
