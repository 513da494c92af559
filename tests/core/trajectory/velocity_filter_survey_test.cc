// The filter on simulated survey legs: spec section 4, tests 5 (accuracy and
// consistency), 6 (gates) and 7 (lock-out).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/trajectory/velocity_filter.h"
#include "tests/core/trajectory/velocity_filter_scenarios.h"

namespace seamap {
namespace {

using namespace seamap::testing;

// ---------------------------------------------------------------------------
// Truth driven by the filter's own model: white body acceleration of density
// q, integrated exactly per step; start drawn from the filter's prior.
// Attitude exact and heading_noise_rad 0: white attitude noise also shortens
// the integrated path by cos(error), a second-order effect the linear filter
// ignores, which (measured, 1000 runs without gates, 1 degree) lifts the mean
// NEES from 2.95 to about 3.2. velocity_filter_test.cc tests the attitude term
// of Q on its own.

struct ConsistencyResult {
  double nis_sum_accepted = 0;
  int accepted = 0;
  double nis_sum_all = 0;
  int updates = 0;
  double final_position_nees = 0;
};

ConsistencyResult FlyOwnModel(const VelocityFilterOptions& options, uint64_t seed, int steps) {
  constexpr double kStepS = 0.2;
  Attitude attitude;
  attitude.roll_rad = -3 * kDeg;
  attitude.pitch_rad = 5 * kDeg;
  attitude.heading_rad = 30 * kDeg;
  const Eigen::Matrix3d ned_from_body = NedFromBody(attitude);
  const double q = options.accel_density;
  Gauss gauss(seed);

  constexpr double kPositionSigma = 0.05, kVelocitySigma = 0.5;
  VelocityFilter filter(options);
  filter.Start(0, 0, 0, 20, kPositionSigma, kVelocitySigma);
  Eigen::Vector3d position_m =
      Eigen::Vector3d(0, 0, 20) + gauss.Vector(Eigen::Vector3d(kPositionSigma, kPositionSigma, kDepthSigma));
  Eigen::Vector3d velocity_mps = gauss.Vector(Eigen::Vector3d::Constant(kVelocitySigma));

  ConsistencyResult result;
  for (int k = 1; k <= steps; ++k) {
    // Per axis, (integral of v increment, v increment) has covariance
    // q [[dT^3/3, dT^2/2], [dT^2/2, dT]]; correlation sqrt(3)/2.
    const Eigen::Vector3d z1 = gauss.Vector(Eigen::Vector3d::Ones());
    const Eigen::Vector3d z2 = gauss.Vector(Eigen::Vector3d::Ones());
    const Eigen::Vector3d dv = std::sqrt(q * kStepS) * z1;
    const Eigen::Vector3d dp_body = std::sqrt(q * kStepS * kStepS * kStepS / 3) * (std::sqrt(3.0) / 2 * z1 + 0.5 * z2);
    position_m += kStepS * ned_from_body * velocity_mps + ned_from_body * dp_body;
    velocity_mps += dv;

    filter.PredictTo(k * kStepS, Constant(attitude));

    const auto outcome = filter.UpdateVelocity(velocity_mps + gauss.Vector(kVoSigma));
    result.nis_sum_all += filter.last_nis();
    ++result.updates;
    if (outcome == VelocityFilter::Outcome::kAccepted) {
      result.nis_sum_accepted += filter.last_nis();
      ++result.accepted;
    }
    filter.UpdateDepth(position_m.z() + kDepthSigma * gauss());
  }
  result.final_position_nees = PositionNees(filter, position_m);
  EXPECT_EQ(result.accepted, filter.counts().velocity_accepted);
  EXPECT_NEAR(result.nis_sum_accepted, filter.counts().velocity_nis_sum, 1e-9 * result.nis_sum_accepted);
  return result;
}

VelocityFilterOptions NoGates() {
  VelocityFilterOptions options;
  options.gate_velocity = options.gate_depth = options.gate_position = 1e9;
  return options;
}

// ---------------------------------------------------------------------------
// Spec test 5: constant-velocity truth, and consistency

// The truth holds its speed, so the filter may assume so too: q = 1e-6 m^2/s^3
// (velocity random walk 1 mm/s per root second). With the default q = 1e-3,
// tuned to follow manoeuvres, 0.01 m/s is out of reach (next test).
VelocityFilterOptions SteadyOptions() {
  VelocityFilterOptions options;
  options.accel_density = 1e-6;
  return options;
}

TEST(VelocityFilterSurveyTest, ConstantVelocityTruthIsTracked) {
  const LegResult leg = FlyConstantVelocityLeg(SteadyOptions(), 1);
  EXPECT_LT(leg.velocity_rms_mps, 0.01);  // 3-D error norm, after the first minute
  EXPECT_LT(leg.final_position_nees, 11.34);
  const int updates = leg.counts.velocity_accepted + leg.counts.velocity_rejected;
  EXPECT_EQ(updates, 3000);
  EXPECT_EQ(leg.counts.reacquisitions, 0);
  EXPECT_LT(leg.counts.velocity_rejected, 0.015 * updates);
  EXPECT_EQ(leg.counts.depth_accepted + leg.counts.depth_rejected, 3000);
  EXPECT_LT(leg.counts.depth_rejected, 0.015 * 3000);
  std::printf("constant velocity, q 1e-6: velocity RMS %.4f m/s, final NEES %.2f, VO gated %d of 3000\n",
              leg.velocity_rms_mps, leg.final_position_nees, leg.counts.velocity_rejected);
}

TEST(VelocityFilterSurveyTest, DefaultTuningVelocityErrorIsTheSteadyStateGain) {
  // u and v are observed by VO alone (level flight, no fixes): each a scalar
  // random walk seen in white noise. Steady-state prior variance
  // M = (Q + sqrt(Q^2 + 4 Q R)) / 2 with Q = q dT, gain K = M / (M + R); for a
  // truth that does not accelerate the error variance is K R / (2 - K).
  const LegResult leg = FlyConstantVelocityLeg(VelocityFilterOptions(), 1);
  const double q_step = VelocityFilterOptions().accel_density * 0.2;
  for (int axis = 0; axis < 2; ++axis) {
    const double r = kVoSigma[axis] * kVoSigma[axis];
    const double m = (q_step + std::sqrt(q_step * q_step + 4 * q_step * r)) / 2;
    const double k = m / (m + r);
    const double expected_rms = std::sqrt(k * r / (2 - k));
    EXPECT_NEAR(leg.velocity_rms_axis_mps[axis], expected_rms, 0.15 * expected_rms) << "axis " << axis;
  }
  EXPECT_GT(leg.velocity_rms_mps, 0.02);  // u alone: K = 0.21, 0.020 m/s
}

TEST(VelocityFilterSurveyTest, ConsistentWithItsOwnProcessNoise) {
  // 50 runs of 3000 steps. Without gates the 150,000 VO innovations are
  // independent chi-square(3): mean 3, sd sqrt(6 / 150000) = 0.0063; band +-4 sd.
  // The final position NEES averaged over 50 runs is chi-square(150) / 50:
  // 99 % band [2.18, 3.97], the spec's [2.2, 4.0].
  //
  // With the 1 % gate the spec's VO band [2.9, 3.1] is mis-centred: the mean of
  // accepted NIS cannot be 3. Truncating chi-square(3) at 11.34 alone gives
  // 3 (1 - P(chi2_5 > 11.34)) / (1 - P(chi2_3 > 11.34)) = 2.894, and skipping
  // the rejected 1 % leaves the state error a little larger than P says
  // (measured over 1000 runs: accepted 2.907, all updates 3.017, NEES 3.16).
  // So: accepted mean in 2.907 +- 0.025 (+-4 sd), NEES in the same 99 % band.
  constexpr int kRuns = 50, kSteps = 3000;
  const auto fly = [&](const VelocityFilterOptions& options) {
    ConsistencyResult total;
    for (int run = 0; run < kRuns; ++run) {
      const ConsistencyResult r = FlyOwnModel(options, 100 + run, kSteps);
      total.nis_sum_accepted += r.nis_sum_accepted;
      total.accepted += r.accepted;
      total.nis_sum_all += r.nis_sum_all;
      total.updates += r.updates;
      total.final_position_nees += r.final_position_nees / kRuns;
    }
    return total;
  };
  VelocityFilterOptions ungated = NoGates();
  ungated.heading_noise_rad = 0;
  const ConsistencyResult free = fly(ungated);
  EXPECT_EQ(free.accepted, kRuns * kSteps);
  EXPECT_NEAR(free.nis_sum_all / free.updates, 3.0, 0.025);
  EXPECT_GT(free.final_position_nees, 2.18);
  EXPECT_LT(free.final_position_nees, 3.97);

  VelocityFilterOptions gated;
  gated.heading_noise_rad = 0;
  const ConsistencyResult g = fly(gated);
  EXPECT_NEAR(g.nis_sum_accepted / g.accepted, 2.907, 0.025);
  const double rejected = 1.0 - static_cast<double>(g.accepted) / g.updates;
  EXPECT_GT(rejected, 0.008);
  EXPECT_LT(rejected, 0.013);
  EXPECT_GT(g.final_position_nees, 2.18);
  EXPECT_LT(g.final_position_nees, 3.97);
  std::printf("ungated: VO NIS %.4f, NEES %.3f; gated: accepted VO NIS %.4f (all %.4f), %.2f %% gated, NEES %.3f\n",
              free.nis_sum_all / free.updates, free.final_position_nees, g.nis_sum_accepted / g.accepted,
              g.nis_sum_all / g.updates, 100 * rejected, g.final_position_nees);
}

// ---------------------------------------------------------------------------
// Spec test 6: gates

TEST(VelocityFilterSurveyTest, VelocityOutlierIsRejectedAndChangesNothing) {
  constexpr int kBad = 1500;
  const LegResult outlier = FlyConstantVelocityLeg(SteadyOptions(), 1, [](int k, Measurements* m) {
    if (k == kBad) m->vo_mps.x() += 1.0;
  });
  const LegResult skipped = FlyConstantVelocityLeg(SteadyOptions(), 1, [](int k, Measurements* m) {
    if (k == kBad) m->use_vo = false;
  });
  EXPECT_EQ(outlier.vo_outcomes[kBad - 1], VelocityFilter::Outcome::kRejected);
  EXPECT_EQ(outlier.counts.velocity_rejected, skipped.counts.velocity_rejected + 1);
  EXPECT_EQ(outlier.counts.velocity_accepted, skipped.counts.velocity_accepted);
  EXPECT_EQ(outlier.counts.reacquisitions, 0);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(outlier.final_state[i], skipped.final_state[i], 1e-12) << i;
}

TEST(VelocityFilterSurveyTest, DepthSpikeIsRejectedAndChangesNothing) {
  constexpr int kBad = 1500;
  const LegResult spike = FlyConstantVelocityLeg(SteadyOptions(), 1, [](int k, Measurements* m) {
    if (k == kBad) m->depth_m += 5.0;
  });
  const LegResult skipped = FlyConstantVelocityLeg(SteadyOptions(), 1, [](int k, Measurements* m) {
    if (k == kBad) m->use_depth = false;
  });
  EXPECT_EQ(spike.depth_outcomes[kBad - 1], VelocityFilter::Outcome::kRejected);
  EXPECT_EQ(spike.counts.depth_rejected, skipped.counts.depth_rejected + 1);
  EXPECT_EQ(spike.counts.depth_accepted, skipped.counts.depth_accepted);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(spike.final_state[i], skipped.final_state[i], 1e-12) << i;
}

// ---------------------------------------------------------------------------
// Spec test 7: lock-out

TEST(VelocityFilterSurveyTest, LockOutFollowsAVelocityStep) {
  // The truth steps from 0.5 to 1.2 m/s at 100 s: far outside the gate, so VO
  // is rejected until 5 agreeing rejections re-acquire (the 5th is applied).
  constexpr double kStepS = 100;
  const auto truth = [](double time_s) { return Eigen::Vector3d(time_s < kStepS ? 0.5 : 1.2, 0, 0); };
  const LegResult leg = FlyConstantVelocityLeg(VelocityFilterOptions(), 1, {}, truth);
  EXPECT_EQ(leg.counts.reacquisitions, 1);
  const int first = static_cast<int>(kStepS / 0.2);  // index of the first VO update after the step
  for (int i = 0; i < 4; ++i) EXPECT_EQ(leg.vo_outcomes[first + i], VelocityFilter::Outcome::kRejected) << i;
  EXPECT_EQ(leg.vo_outcomes[first + 4], VelocityFilter::Outcome::kReacquired);
  double worst_mps = 0;
  for (size_t i = 0; i < leg.times_s.size(); ++i) {
    if (leg.times_s[i] >= kStepS + 5) worst_mps = std::max(worst_mps, std::abs(leg.velocity_errors_mps[i].x()));
  }
  EXPECT_LT(worst_mps, 0.1);

  // Without the lock-out (never 10^6 agreeing rejections) P only grows by q dT
  // per rejected step: the gate opens after about 40 s, not within 5.
  VelocityFilterOptions stuck;
  stuck.lockout_velocity_count = 1000000;
  const LegResult no_lockout = FlyConstantVelocityLeg(stuck, 1, {}, truth);
  EXPECT_EQ(no_lockout.counts.reacquisitions, 0);
  const size_t at_105_s = static_cast<size_t>((kStepS + 5) / 0.2) - 1;
  ASSERT_NEAR(no_lockout.times_s[at_105_s], kStepS + 5, 1e-9);
  EXPECT_GT(std::abs(no_lockout.velocity_errors_mps[at_105_s].x()), 0.5);
}

TEST(VelocityFilterSurveyTest, DisagreeingRejectionsDoNotReacquire) {
  // Outliers alternating +-1 m/s on u do not agree with one another: the
  // sensor is wrong, not the filter.
  const LegResult leg = FlyConstantVelocityLeg(VelocityFilterOptions(), 1, [](int k, Measurements* m) {
    if (k > 1000 && k <= 1020) m->vo_mps.x() += k % 2 ? 1.0 : -1.0;
  });
  EXPECT_EQ(leg.counts.reacquisitions, 0);
  for (int k = 1001; k <= 1020; ++k) EXPECT_EQ(leg.vo_outcomes[k - 1], VelocityFilter::Outcome::kRejected) << k;
}

}  // namespace
}  // namespace seamap
