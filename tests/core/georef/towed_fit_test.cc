#include "core/georef/towed_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "core/georef/tether_model.h"

namespace seamap {
namespace {

// Four 100 m legs 20 m apart, joined by semicircles, at 0.6 m/s and 6 m
// depth, a 15 m tether (reach 13.75 m). The buoy either pulled along the
// tether (a tractrix) or running in the vehicle's wake; fixes at 1 Hz.
// Truth: world = s R slam + t.
struct Survey {
  Similarity truth;
  std::vector<Keyframe> keyframes;
  std::vector<BuoyFix> fixes;
  std::vector<double> reach, depth;
};

Eigen::Vector2d PathAt(double s) {
  const double leg = 100, r = 10, turn = M_PI * r;
  for (int k = 0; k < 4; ++k) {
    const double x = 20.0 * k;
    const bool north = k % 2 == 0;
    if (s <= leg) return {x, north ? s : leg - s};
    s -= leg;
    if (k == 3) break;
    if (s <= turn) {
      const double a = s / r;  // over the top after a northward leg, under the bottom otherwise
      return north ? Eigen::Vector2d(x + r - r * std::cos(a), leg + r * std::sin(a))
                   : Eigen::Vector2d(x + r - r * std::cos(a), -r * std::sin(a));
    }
    s -= turn;
  }
  return {60, 100 + s};
}

Survey MakeSurvey(bool wake, double gps_sigma_m, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  Survey c;
  c.truth.scale = 0.37;
  c.truth.rotation = Eigen::AngleAxisd(2.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  c.truth.translation = {40, -25, 3};
  const double speed = 0.6, depth = 6, reach = std::sqrt(15.0 * 15.0 - depth * depth);
  const double duration = (400 + 3 * M_PI * 10) / speed;
  TowedBuoy buoy(PathAt(0) - Eigen::Vector2d(0, reach));
  for (int k = 0; k * 0.01 <= duration; ++k) {
    const double t = k * 0.01, s = speed * t;
    const Eigen::Vector2d vehicle = PathAt(s);
    if (wake)
      buoy = TowedBuoy(s >= reach ? PathAt(s - reach) : Eigen::Vector2d(0, s - reach));
    else
      buoy.Step(vehicle, reach);
    if (k % 100 == 0)
      c.fixes.push_back({t, buoy.position() + gps_sigma_m * Eigen::Vector2d(noise(rng), noise(rng)), 0, 0, k});
    if (k % 100 == 50) {
      const Eigen::Vector3d world(vehicle.x(), vehicle.y(), -depth);
      Keyframe kf;
      kf.time_s = t;
      kf.position_slam = c.truth.rotation.transpose() * (world - c.truth.translation) / c.truth.scale;
      kf.world_from_cam = Eigen::Quaterniond::Identity();
      c.keyframes.push_back(kf);
      c.reach.push_back(reach);
      c.depth.push_back(depth);
    }
  }
  return c;
}

double Rmse(const Survey& c, const Similarity& fit) {
  double sq = 0;
  for (const Keyframe& k : c.keyframes)
    sq += (fit.Apply(k.position_slam) - c.truth.Apply(k.position_slam)).head<2>().squaredNorm();
  return std::sqrt(sq / c.keyframes.size());
}

TowedFitResult Fit(const Survey& c) {
  const SlamPath path(c.keyframes, SlamPath::Options{});
  const BuoyTrack buoy(c.fixes);
  const Similarity start = WakeStart(path, c.reach, c.depth, buoy, 0.6);
  return FitTowedBuoy(path, c.reach, c.depth, buoy, start, 0, TowedFitOptions{});
}

TEST(WakeStart, LandsWithinAFewMetres) {
  const Survey c = MakeSurvey(false, 1.5, 1);
  const SlamPath path(c.keyframes, SlamPath::Options{});
  const Similarity start = WakeStart(path, c.reach, c.depth, BuoyTrack(c.fixes), 0.6);
  EXPECT_LT(Rmse(c, start), 3.0);
}

TEST(FitTowedBuoy, NoiseFreeTractrixRecoveredExactly) {
  const Survey c = MakeSurvey(false, 0, 1);
  const TowedFitResult r = Fit(c);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(Rmse(c, r.fit), 0.01);
  EXPECT_NEAR(r.fit.scale / c.truth.scale, 1, 1e-3);
  EXPECT_LT(r.wake_share, 0.05);
  EXPECT_NEAR(r.reach_factor, 1, 0.005);
}

TEST(FitTowedBuoy, NoiseFreeWakeFollowerRecoveredExactly) {
  const Survey c = MakeSurvey(true, 0, 1);
  const TowedFitResult r = Fit(c);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(Rmse(c, r.fit), 0.01);
  EXPECT_GT(r.wake_share, 0.95);
}

TEST(FitTowedBuoy, TellsTheFollowerApartAndPredictsItsError) {
  // Over 8 noisy surveys of each kind: the right model, and the predicted
  // error within 0.67-1.5 of the actual one (RMS over the surveys).
  for (bool wake : {false, true}) {
    double actual = 0, predicted = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
      const Survey c = MakeSurvey(wake, 1.5, seed);
      const TowedFitResult r = Fit(c);
      ASSERT_TRUE(r.ok);
      EXPECT_NEAR(r.wake_share, wake ? 1 : 0, 0.2) << seed;
      const double e = Rmse(c, r.fit);
      EXPECT_LT(e, 0.6) << seed;
      actual += e * e;
      predicted += r.predicted_rmse_m * r.predicted_rmse_m;
      ASSERT_EQ(r.keyframe_sigma_m.size(), c.keyframes.size());
    }
    const double ratio = std::sqrt(actual / predicted);
    EXPECT_GT(ratio, 0.67) << (wake ? "wake" : "tractrix");
    EXPECT_LT(ratio, 1.5) << (wake ? "wake" : "tractrix");
  }
}

TEST(FitTowedBuoy, MultipathFixesDropped) {
  Survey c = MakeSurvey(false, 0.5, 3);
  for (size_t j = 7; j < c.fixes.size(); j += 23) c.fixes[j].position_en_m += Eigen::Vector2d(14, -14);
  const TowedFitResult r = Fit(c);
  ASSERT_TRUE(r.ok);
  EXPECT_GE(r.outliers, static_cast<int>(c.fixes.size() / 23) - 1);
  EXPECT_LT(Rmse(c, r.fit), 0.2);
}

}  // namespace
}  // namespace seamap
