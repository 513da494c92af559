#include "core/sim/survey_path.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(SurveyPathTest, LawnmowerLinesAreSpacedAndHeadedAlongTheLines) {
  const SurveyPath path = SurveyPath::Lawnmower(10, 1.5, 30);
  const double turn = M_PI * 0.75;
  // 3 lines and 2 turns are the first layout at least 30 m long.
  EXPECT_NEAR(path.Length(), 3 * 10 + 2 * turn, 1e-9);

  const LocalXY mid0 = path.PositionAt(5);
  const LocalXY mid1 = path.PositionAt(10 + turn + 5);
  const LocalXY mid2 = path.PositionAt(2 * (10 + turn) + 5);
  EXPECT_NEAR(mid0.east, 0, 1e-9);
  EXPECT_NEAR(mid0.north, 5, 1e-9);
  EXPECT_NEAR(mid1.east - mid0.east, 1.5, 1e-9);
  EXPECT_NEAR(mid2.east - mid1.east, 1.5, 1e-9);
  EXPECT_NEAR(mid1.north, 5, 1e-9);
  EXPECT_NEAR(path.HeadingAt(5), 0, 1e-9);
  EXPECT_NEAR(path.HeadingAt(10 + turn + 5), 180, 1e-9);
  EXPECT_NEAR(path.HeadingAt(2 * (10 + turn) + 5), 0, 1e-9);

  // Half way through the first turn: at its top, heading east.
  const LocalXY top = path.PositionAt(10 + turn / 2);
  EXPECT_NEAR(top.east, 0.75, 1e-9);
  EXPECT_NEAR(top.north, 10.75, 1e-9);
  EXPECT_NEAR(path.HeadingAt(10 + turn / 2), 90, 1e-6);
  // Half way through the second (bottom) turn: heading east again.
  EXPECT_NEAR(path.HeadingAt(2 * 10 + 1.5 * turn), 90, 1e-6);
  EXPECT_NEAR(path.PositionAt(2 * 10 + 1.5 * turn).north, -0.75, 1e-9);
}

TEST(SurveyPathTest, TrajectoryMovesAtTheSpeedWithinAttitudeLimits) {
  const SurveyPath path = SurveyPath::Lawnmower(25, 1.2, 40);
  TrajectoryOptions o;
  o.frames = 200;
  const auto poses = MakeTrajectory(path, o, 7);
  ASSERT_EQ(poses.size(), 200u);
  for (size_t i = 1; i < poses.size(); ++i) {
    const VehiclePose &a = poses[i - 1].pose, &b = poses[i].pose;
    EXPECT_NEAR(poses[i].time_s - poses[i - 1].time_s, 0.2, 1e-12);
    // On the straight first line (25 m, 200 frames at 0.1 m) each step is 0.1 m north.
    EXPECT_NEAR(std::hypot(b.east_m - a.east_m, b.north_m - a.north_m), 0.1, 1e-9);
    EXPECT_NEAR(b.heading_deg, 0, 1e-9);
    // Smooth: small changes between frames.
    EXPECT_LT(std::fabs(b.altitude_m - a.altitude_m), 0.02);
    EXPECT_LT(std::fabs(b.pitch_deg - a.pitch_deg), 0.6);
  }
  double alt_lo = 1e9, alt_hi = -1e9, pitch_hi = 0, roll_hi = 0;
  for (const auto& tp : poses) {
    alt_lo = std::min(alt_lo, tp.pose.altitude_m);
    alt_hi = std::max(alt_hi, tp.pose.altitude_m);
    pitch_hi = std::max(pitch_hi, std::fabs(tp.pose.pitch_deg));
    roll_hi = std::max(roll_hi, std::fabs(tp.pose.roll_deg));
    EXPECT_NEAR(tp.pose.depth_m, 35 - tp.pose.altitude_m, 1e-12);
  }
  EXPECT_GE(alt_lo, 1.6);
  EXPECT_LE(alt_hi, 2.0);
  EXPECT_GT(alt_hi - alt_lo, 0.1);  // it does vary
  EXPECT_LE(pitch_hi, 3.0);
  EXPECT_GT(pitch_hi, 1.0);
  EXPECT_LE(roll_hi, 2.0);
  EXPECT_GT(roll_hi, 0.5);
}

TEST(SurveyPathTest, TrajectoryIsDeterministicPerSeed) {
  const SurveyPath path = SurveyPath::Lawnmower(10, 1, 10);
  TrajectoryOptions o;
  o.frames = 20;
  const auto a = MakeTrajectory(path, o, 3), b = MakeTrajectory(path, o, 3), c = MakeTrajectory(path, o, 4);
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].pose.altitude_m, b[i].pose.altitude_m);
    EXPECT_EQ(a[i].pose.roll_deg, b[i].pose.roll_deg);
  }
  EXPECT_NE(a[5].pose.altitude_m, c[5].pose.altitude_m);
}

TEST(SurveyPathTest, TrajectoryStopsAtTheEndOfAShortPath) {
  const SurveyPath path = SurveyPath::FromWaypoints({{0, 0}, {1, 0}});
  TrajectoryOptions o;
  o.frames = 100;
  const auto poses = MakeTrajectory(path, o, 1);
  EXPECT_EQ(poses.size(), 11u);  // 0, 0.1, ..., 1.0 m
  EXPECT_NEAR(poses.back().pose.east_m, 1.0, 1e-9);
  EXPECT_NEAR(poses[3].pose.heading_deg, 90, 1e-9);
}

TEST(SurveyPathTest, LoadsWaypointCsvAndNamesBadCells) {
  testing::TempDir dir;
  const auto good = testing::WriteFile(dir / "path.csv", "name,x_m,y_m\na,0,0\nb,3,4\n\nc,3,10\n");
  const SurveyPath path = SurveyPath::LoadCsv(good.string());
  EXPECT_NEAR(path.Length(), 11, 1e-12);
  EXPECT_NEAR(path.PositionAt(2.5).east, 1.5, 1e-12);

  const auto bad = testing::WriteFile(dir / "bad.csv", "x_m,y_m\n0,0\n1,abc\n");
  try {
    SurveyPath::LoadCsv(bad.string());
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "y_m");
  }
  const auto no_column = testing::WriteFile(dir / "nocol.csv", "x,y\n0,0\n1,1\n");
  EXPECT_THROW(SurveyPath::LoadCsv(no_column.string()), InputError);
  const auto one_point = testing::WriteFile(dir / "one.csv", "x_m,y_m\n0,0\n");
  EXPECT_THROW(SurveyPath::LoadCsv(one_point.string()), InputError);
}

TEST(SurveyPathTest, NavigationErrorsAreOffByDefaultAndHaveTheRequestedSize) {
  const SurveyPath path = SurveyPath::Lawnmower(100, 1, 100);
  TrajectoryOptions o;
  o.frames = 1000;
  const auto truth = MakeTrajectory(path, o, 1);
  const auto exact = AddNavigationErrors(truth, {}, 1);
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(exact[i].pose.east_m, truth[i].pose.east_m);
    EXPECT_EQ(exact[i].pose.heading_deg, truth[i].pose.heading_deg);
  }

  NavErrorOptions noise;
  noise.position_sigma_m = 0.1;
  noise.heading_sigma_deg = 1;
  const auto noisy = AddNavigationErrors(truth, noise, 1);
  double sum_e = 0, sum_h = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    sum_e += std::pow(noisy[i].pose.east_m - truth[i].pose.east_m, 2);
    double dh = std::remainder(noisy[i].pose.heading_deg - truth[i].pose.heading_deg, 360.0);
    sum_h += dh * dh;
    EXPECT_EQ(noisy[i].pose.altitude_m, truth[i].pose.altitude_m);
  }
  EXPECT_NEAR(std::sqrt(sum_e / truth.size()), 0.1, 0.01);
  EXPECT_NEAR(std::sqrt(sum_h / truth.size()), 1.0, 0.1);

  NavErrorOptions drift;
  drift.drift_m_per_min = 0.6;
  const auto drifted = AddNavigationErrors(truth, drift, 1);
  for (size_t i : {0, 300, 999}) {
    const double err =
        std::hypot(drifted[i].pose.east_m - truth[i].pose.east_m, drifted[i].pose.north_m - truth[i].pose.north_m);
    EXPECT_NEAR(err, 0.6 * truth[i].time_s / 60, 1e-9);
  }
}

}  // namespace
}  // namespace seamap
