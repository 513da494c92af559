#include "core/trajectory/trajectory_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/trajectory/track_pairing.h"
#include "core/util/error.h"

namespace seamap {
namespace {

NavRecord Rec(const std::string& image, std::optional<double> time_s, double east, double north, double heading,
              double depth = 30) {
  NavRecord r;
  r.image = image;
  r.time_s = time_s;
  r.pose.east_m = east;
  r.pose.north_m = north;
  r.pose.heading_deg = heading;
  r.pose.depth_m = depth;
  r.pose.altitude_m = 2;
  return r;
}

NavTable Table(const std::string& source, std::vector<NavRecord> records) {
  NavTable t;
  t.source = source;
  t.records = std::move(records);
  for (const auto& r : t.records) {
    t.has_images = t.has_images || !r.image.empty();
    t.has_times = t.has_times || r.time_s.has_value();
  }
  return t;
}

// The estimate: truth moved by a function of the record.
template <typename Move>
NavTable Moved(const NavTable& truth, Move move) {
  NavTable est = truth;
  est.source = "estimate.csv";
  for (auto& r : est.records) move(r);
  return est;
}

// Three passes north/south of 5 m, 0.6 m apart, frames every 0.1 m (0.2 s),
// semicircular turns sampled every 15 degrees (11 frames each).
NavTable Lawnmower() {
  std::vector<NavRecord> records;
  auto add = [&](double east, double north, double heading) {
    const int i = static_cast<int>(records.size());
    records.push_back(Rec("f" + std::to_string(i) + ".jpg", 0.2 * i, east, north, heading));
  };
  const double r = 0.3;
  for (int k = 0; k < 3; ++k) {
    const bool north = k % 2 == 0;
    const double x = 0.6 * k;
    for (int i = 0; i <= 50; ++i) add(x, north ? i * 0.1 : 5 - i * 0.1, north ? 0 : 180);
    if (k == 2) break;
    for (int j = 1; j < 12; ++j) {
      const double theta = M_PI * j / 12;
      if (north)
        add(x + r - r * std::cos(theta), 5 + r * std::sin(theta), 15.0 * j);
      else
        add(x + r - r * std::cos(theta), -r * std::sin(theta), 180 - 15.0 * j);
    }
  }
  return Table("truth.csv", records);
}

TEST(TrajectoryEval, ConstantOffset) {
  const NavTable truth = Lawnmower();
  const NavTable est = Moved(truth, [](NavRecord& r) {
    r.pose.east_m += 0.3;
    r.pose.north_m -= 0.4;
  });
  const TrajectoryErrors e = EvaluateTrajectory(est, truth);
  EXPECT_EQ(e.frames, 3 * 51 + 2 * 11);
  EXPECT_EQ(e.paired_by, "image");
  EXPECT_NEAR(e.ate_m, 0.5, 1e-12);
  EXPECT_NEAR(e.rmse_east_m, 0.3, 1e-12);
  EXPECT_NEAR(e.rmse_north_m, 0.4, 1e-12);
  EXPECT_NEAR(e.max_error_m, 0.5, 1e-12);
  EXPECT_NEAR(e.max_east_m, 0.3, 1e-12);
  EXPECT_NEAR(e.max_north_m, 0.4, 1e-12);
  EXPECT_NEAR(e.end_error_m, 0.5, 1e-12);
  // 3 x 5 m of lines, 2 turns of 12 chords of 2 r sin(7.5 deg).
  const double path = 15 + 2 * 12 * 2 * 0.3 * std::sin(M_PI / 24);
  EXPECT_NEAR(e.path_length_m, path, 1e-9);
  EXPECT_NEAR(e.drift_percent, 0.5 / path * 100, 1e-9);
  // A rigid offset moves neighbouring passes together: no cross-pass error.
  EXPECT_EQ(e.lines, 3);
  EXPECT_GT(e.cross_pairs, 100);
  EXPECT_NEAR(e.cross_median_mm, 0, 1e-6);
  EXPECT_NEAR(e.cross_max_mm, 0, 1e-6);
  EXPECT_EQ(e.velocity_frames, e.frames - 2);
  for (const AxisStats& s : e.velocity) EXPECT_NEAR(s.rmse, 0, 1e-9);
}

// Passes A (north), B (south, 0.6 m east of A), C (north, `c_east` m east of A),
// 5 frames 1 m apart each, joined by 3 turn frames; frame k at t = k s.
NavTable ThreePasses(double c_east) {
  std::vector<NavRecord> r;
  auto add = [&](double east, double north, double heading) {
    r.push_back(Rec("f" + std::to_string(r.size()) + ".jpg", static_cast<double>(r.size()), east, north, heading));
  };
  for (int k = 0; k < 5; ++k) add(0, k, 0);
  add(0.1, 4.3, 45), add(0.3, 4.4, 90), add(0.5, 4.3, 135);
  for (int k = 4; k >= 0; --k) add(0.6, k, 180);
  add(0.7, -0.3, 135), add(c_east - 0.3, -0.4, 90), add(c_east - 0.1, -0.3, 45);
  for (int k = 0; k < 5; ++k) add(c_east, k, 0);
  return Table("truth.csv", r);
}

TEST(TrajectoryEval, LinearDriftAndCrossPassPairsUnderOneMetre) {
  const double rate = 0.01;  // m/s east
  auto drift = [&](NavRecord& r) { r.pose.east_m += rate * *r.time_s; };
  // C 1.01 m from B: only A-B pairs (A_k with B_k, 0.6 m apart), at t = k and 12 - k.
  const NavTable truth = ThreePasses(1.61);
  const TrajectoryErrors e = EvaluateTrajectory(Moved(truth, drift), truth);
  EXPECT_EQ(e.frames, 21);
  EXPECT_EQ(e.lines, 3);
  double sum_sq = 0;
  for (int t = 0; t <= 20; ++t) sum_sq += (rate * t) * (rate * t);
  EXPECT_NEAR(e.ate_m, std::sqrt(sum_sq / 21), 1e-12);
  EXPECT_NEAR(e.rmse_north_m, 0, 1e-12);
  EXPECT_NEAR(e.max_error_m, 0.2, 1e-12);
  EXPECT_NEAR(e.end_error_m, 0.2, 1e-12);
  // Errors 10 mm per second apart: 4, 6, 8, 10, 12 s -> 40 ... 120 mm.
  EXPECT_EQ(e.cross_pairs, 5);
  EXPECT_NEAR(e.cross_median_mm, 80, 1e-9);
  EXPECT_NEAR(e.cross_p90_mm, 112, 1e-9);  // rank 3.6: 100 + 0.6 x 20
  EXPECT_NEAR(e.cross_max_mm, 120, 1e-9);

  // C 0.99 m from B: B_k and C_k pair too (t = 12 - k and 16 + k).
  const NavTable closer = ThreePasses(1.59);
  const TrajectoryErrors c = EvaluateTrajectory(Moved(closer, drift), closer);
  EXPECT_EQ(c.cross_pairs, 10);
  EXPECT_NEAR(c.cross_median_mm, 80, 1e-9);
  EXPECT_NEAR(c.cross_p90_mm, 120, 1e-9);

  // Frames of one pass never pair, however close: a single line has no pairs.
  std::vector<NavRecord> one;
  for (int k = 0; k < 20; ++k) one.push_back(Rec("g" + std::to_string(k), k * 0.2, 0, 0.1 * k, 0));
  const NavTable line = Table("truth.csv", one);
  const TrajectoryErrors l = EvaluateTrajectory(Moved(line, drift), line);
  EXPECT_EQ(l.lines, 1);
  EXPECT_EQ(l.cross_pairs, 0);
  EXPECT_TRUE(std::isnan(l.cross_median_mm));
}

TEST(TrajectoryEval, BodyVelocityErrorsHaveTheVehiclesSigns) {
  // Eastbound at 0.5 m/s; the estimate drifts east (ahead), north (to port) and down.
  std::vector<NavRecord> records;
  for (int k = 0; k <= 10; ++k) records.push_back(Rec("h" + std::to_string(k), 0.2 * k, 0.1 * k, 0, 90));
  NavTable truth = Table("truth.csv", records);
  const double re = 0.02, rn = 0.01, rd = 0.005;
  auto drift = [&](NavRecord& r) {
    r.pose.east_m += re * *r.time_s;
    r.pose.north_m += rn * *r.time_s;
    r.pose.depth_m += rd * *r.time_s;
  };
  TrajectoryErrors e = EvaluateTrajectory(Moved(truth, drift), truth);
  EXPECT_EQ(e.velocity_frames, 9);
  EXPECT_NEAR(e.velocity[0].mean, re, 1e-9);   // u: surge, ahead
  EXPECT_NEAR(e.velocity[1].mean, -rn, 1e-9);  // v: starboard is south
  EXPECT_NEAR(e.velocity[2].mean, rd, 1e-9);   // w: down
  for (const AxisStats& s : e.velocity) {
    EXPECT_NEAR(s.rmse, std::fabs(s.mean), 1e-9);
    EXPECT_NEAR(s.std, 0, 1e-7);
  }
  // Bow up 10 degrees: the body z axis leans forward, so moving ahead is partly "down".
  const double pitch = 10 * M_PI / 180;
  for (auto& r : truth.records) r.pose.pitch_deg = 10;
  e = EvaluateTrajectory(Moved(truth, drift), truth);
  EXPECT_NEAR(e.velocity[0].mean, std::cos(pitch) * re - std::sin(pitch) * rd, 1e-9);
  EXPECT_NEAR(e.velocity[1].mean, -rn, 1e-9);
  EXPECT_NEAR(e.velocity[2].mean, std::sin(pitch) * re + std::cos(pitch) * rd, 1e-9);
}

TEST(TrajectoryEval, PeriodicNoise) {
  // North at 0.5 m/s; east error a, 0, -a, 0, ... : ATE a / sqrt(2). Central
  // differences see -a/dt, 0, +a/dt, 0, ... on sway (v), RMS a / (dt sqrt(2)).
  const double a = 0.004, dt = 0.2;
  std::vector<NavRecord> records;
  for (int k = 0; k < 40; ++k) records.push_back(Rec("n" + std::to_string(k), dt * k, 0, 0.1 * k, 0));
  const NavTable truth = Table("truth.csv", records);
  const NavTable est = Moved(truth, [&](NavRecord& r) {
    const int k = static_cast<int>(std::lround(*r.time_s / dt)) % 4;
    r.pose.east_m += k == 0 ? a : k == 2 ? -a : 0;
  });
  const TrajectoryErrors e = EvaluateTrajectory(est, truth);
  EXPECT_NEAR(e.ate_m, a / std::sqrt(2), 1e-12);
  EXPECT_NEAR(e.max_error_m, a, 1e-12);
  EXPECT_NEAR(e.rmse_east_m, a / std::sqrt(2), 1e-12);
  EXPECT_NEAR(e.path_length_m, 3.9, 1e-9);
  EXPECT_NEAR(e.drift_percent, a / 3.9 * 100, 1e-9);
  const AxisStats& v = e.velocity[1];
  EXPECT_EQ(e.velocity_frames, 38);
  EXPECT_NEAR(v.rmse, a / (dt * std::sqrt(2)), 1e-9);
  EXPECT_NEAR(v.mean, -a / (38 * dt), 1e-9);  // 10 negative, 9 positive
  EXPECT_NEAR(v.rmse * v.rmse, v.mean * v.mean + v.std * v.std, 1e-12);
  EXPECT_NEAR(e.velocity[0].rmse, 0, 1e-12);
  EXPECT_NEAR(e.velocity[2].rmse, 0, 1e-12);
}

TEST(TrajectoryEval, RandomNoiseMatchesItsOwnStatistics) {
  const NavTable truth = Lawnmower();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.005);
  std::vector<double> de, dn;
  const NavTable est = Moved(truth, [&](NavRecord& r) {
    de.push_back(noise(rng));
    dn.push_back(noise(rng));
    r.pose.east_m += de.back();
    r.pose.north_m += dn.back();
  });
  double sum_sq = 0, max = 0;
  for (size_t i = 0; i < de.size(); ++i) {
    sum_sq += de[i] * de[i] + dn[i] * dn[i];
    max = std::max(max, std::hypot(de[i], dn[i]));
  }
  const TrajectoryErrors e = EvaluateTrajectory(est, truth);
  EXPECT_NEAR(e.ate_m, std::sqrt(sum_sq / de.size()), 1e-12);
  EXPECT_NEAR(e.max_error_m, max, 1e-12);
  EXPECT_NEAR(e.end_error_m, std::hypot(de.back(), dn.back()), 1e-12);
  // Pair errors are differences of two independent 2D errors: Rayleigh with
  // sigma 5 sqrt(2) mm, median 8.3 mm.
  EXPECT_NEAR(e.cross_median_mm, 5 * std::sqrt(2) * std::sqrt(2 * std::log(2)), 1.5);
}

TEST(TrajectoryEval, PairsByImageInAnyOrderElseByTime) {
  const NavTable truth = Lawnmower();
  NavTable est = Moved(truth, [](NavRecord& r) { r.pose.east_m += 0.1; });
  std::reverse(est.records.begin(), est.records.end());
  est.records.resize(100);  // the last 100 frames of the survey
  est.records.push_back(Rec("not_in_truth.jpg", 1e6, 50, 50, 0));
  TrajectoryErrors e = EvaluateTrajectory(est, truth);
  EXPECT_EQ(e.frames, 100);
  EXPECT_NEAR(e.max_error_m, 0.1, 1e-12);
  EXPECT_NEAR(e.end_error_m, 0.1, 1e-12);

  // No names: the nearest time within a quarter frame interval (0.05 s here).
  EXPECT_NEAR(TimePairingTolerance(truth), 0.05, 1e-12);
  NavTable timed = Moved(truth, [](NavRecord& r) {
    r.image.clear();
    *r.time_s += 0.03;
  });
  timed.has_images = false;
  e = EvaluateTrajectory(timed, truth);
  EXPECT_EQ(e.paired_by, "time");
  EXPECT_EQ(e.frames, static_cast<int>(truth.records.size()));
  EXPECT_NEAR(e.ate_m, 0, 1e-12);

  NavTable late = Moved(timed, [](NavRecord& r) { *r.time_s += 0.05; });  // 0.08 s off
  try {
    EvaluateTrajectory(late, truth);
    FAIL() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "estimate.csv");
    const std::string what = error.what();
    EXPECT_NE(what.find("no frame in common with truth.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("no image names"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace seamap
