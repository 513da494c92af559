#include "core/georef/tether.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/georef/buoy_track.h"
#include "core/georef/tether_model.h"

namespace seamap {
namespace {

TEST(TetherReach, PythagorasAndItsLimits) {
  EXPECT_NEAR(TetherReach(30, 12.5), 27.2718, 1e-4);
  EXPECT_DOUBLE_EQ(TetherReach(30, 30), 0.0);
  EXPECT_DOUBLE_EQ(TetherReach(30, 0), 30.0);
  EXPECT_THROW(TetherReach(30, 31), std::invalid_argument);
  EXPECT_THROW(TetherReach(30, -1), std::invalid_argument);
  EXPECT_THROW(TetherReach(0, 0), std::invalid_argument);
}

TEST(VehicleFromBuoy, TheVehicleIsAheadOfTheTrailingBuoy) {
  const Eigen::Vector2d north = VehicleFromBuoy({0, 0}, {0, 0.5}, 10);  // towed north
  EXPECT_NEAR(north.x(), 0, 1e-12);
  EXPECT_NEAR(north.y(), 10, 1e-12);
  const Eigen::Vector2d east = VehicleFromBuoy({0, 0}, {3, 0}, 10);  // towed east
  EXPECT_NEAR(east.x(), 10, 1e-12);
  EXPECT_NEAR(east.y(), 0, 1e-12);
}

TEST(TautTime, TwiceTheReachAtTheSpeed) {
  EXPECT_NEAR(TautTime(27.27, 0.6), 90.9, 0.01);  // units of seconds, not the paper's 1/s
}

TEST(DirectionWindow, TheSpecsExample) {
  // sigma 1.5 m, 1 Hz, 0.5 m/s, c_t 28 m: about 53 s, and there the
  // sideways error c_t sigma_theta is half a sigma.
  const double window = DirectionWindow(1.5, 0.5, 1.0, 28);
  EXPECT_NEAR(window, 53, 1.5);
  EXPECT_NEAR(28 * WindowDirectionSigma(1.5, 0.5, 1.0, window), 0.75, 1e-9);
  EXPECT_LT(DirectionWindow(0, 0.5, 1.0, 28), 1e-9);  // clean fixes: as short as the caller allows
}

// A straight tow with noisy fixes: the windowed fit's direction error is what
// the formula says; a single fix difference is far worse.
TEST(DirectionWindow, WindowedDirectionMatchesTheFormulaOnAStraightTow) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> noise(0, 1.5);
  const double speed = 0.5, window = 53;
  std::vector<double> fitted, single;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<BuoyFix> fixes;
    for (int j = 0; j <= 120; ++j) fixes.push_back({double(j), {noise(rng), speed * j + noise(rng)}, 1.5, 0, j + 2});
    const BuoyTrack track(fixes);
    const BuoyLocalFit fit = track.FitAt(60, window, 0, 120);
    ASSERT_TRUE(fit.ok);
    fitted.push_back(std::atan2(fit.velocity_en_mps.x(), fit.velocity_en_mps.y()));
    const Eigen::Vector2d step = track.fixes()[61].position_en_m - track.fixes()[60].position_en_m;
    single.push_back(std::atan2(step.x(), step.y()));
  }
  auto rms = [](const std::vector<double>& v) {
    double sq = 0;
    for (double x : v) sq += x * x;
    return std::sqrt(sq / v.size());
  };
  // The quadratic's slope at the window centre: sigma_theta for a straight
  // line fit (sqrt(12) / T^1.5) grows by the quadratic term's share; within 20 %.
  const double formula = WindowDirectionSigma(1.5, speed, 1.0, window);
  EXPECT_NEAR(rms(fitted) / formula, 1.0, 0.2);
  EXPECT_GT(rms(single), 10 * rms(fitted));
}

TEST(TowedBuoy, TracesATractrixAfterARightAngleTurn) {
  // The buoy trails at c_t behind a vehicle heading east, which turns north:
  // after s metres the buoy is c_t sech(s / c_t) off the new line.
  const double reach = 20;
  TowedBuoy buoy({-reach, 0});
  bool taut = false;
  for (double s = 0; s <= 80; s += 0.001) taut = buoy.Step({0, s}, reach);
  EXPECT_TRUE(taut);
  EXPECT_NEAR(-buoy.position().x(), reach / std::cosh(80 / reach), 0.01);
  TowedBuoy slack({-5, 0});
  EXPECT_FALSE(slack.Step({0, 0}, reach));  // inside the reach: stays
  EXPECT_DOUBLE_EQ(slack.position().x(), -5);
}

}  // namespace
}  // namespace seamap
