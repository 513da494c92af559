#include "core/trajectory/velocity_filter.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"
#include "tests/core/trajectory/velocity_filter_scenarios.h"

namespace seamap {
namespace {

using namespace seamap::testing;

// ---------------------------------------------------------------------------
// Options

TEST(VelocityFilterOptionsTest, DefaultsPass) {
  EXPECT_NO_THROW(VelocityFilterOptions().Check());
}

TEST(VelocityFilterOptionsTest, CheckNamesTheBadOption) {
  const std::vector<std::pair<std::string, std::function<void(VelocityFilterOptions*)>>> cases = {
      {"accel_density", [](VelocityFilterOptions* o) { o->accel_density = 0; }},
      {"accel_density", [](VelocityFilterOptions* o) { o->accel_density = NAN; }},
      {"heading_noise_rad", [](VelocityFilterOptions* o) { o->heading_noise_rad = -0.1; }},
      {"pitch_noise_rad", [](VelocityFilterOptions* o) { o->pitch_noise_rad = -1; }},
      {"roll_noise_rad", [](VelocityFilterOptions* o) { o->roll_noise_rad = INFINITY; }},
      {"vo_sigma_mps", [](VelocityFilterOptions* o) { o->vo_sigma_mps.z() = 0; }},
      {"depth_sigma_m", [](VelocityFilterOptions* o) { o->depth_sigma_m = -0.02; }},
      {"position_sigma_m", [](VelocityFilterOptions* o) { o->position_sigma_m = 0; }},
      {"max_step_s", [](VelocityFilterOptions* o) { o->max_step_s = 0; }},
      {"gate_velocity", [](VelocityFilterOptions* o) { o->gate_velocity = -1; }},
      {"gate_depth", [](VelocityFilterOptions* o) { o->gate_depth = 0; }},
      {"gate_position", [](VelocityFilterOptions* o) { o->gate_position = NAN; }},
      {"lockout_velocity_count", [](VelocityFilterOptions* o) { o->lockout_velocity_count = 1; }},
      {"lockout_position_s", [](VelocityFilterOptions* o) { o->lockout_position_s = 0; }},
  };
  for (const auto& [field, spoil] : cases) {
    VelocityFilterOptions options;
    spoil(&options);
    try {
      options.Check();
      ADD_FAILURE() << field << ": no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field);
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
    EXPECT_THROW(VelocityFilter{options}, InputError) << field;
  }
}

// ---------------------------------------------------------------------------
// Axes, signs, attitude

TEST(VelocityFilterTest, NedFromBodyMatchesFrameProjector) {
  for (const auto& [heading, pitch, roll] :
       std::vector<std::array<double, 3>>{{0, 0, 0}, {90, 0, 0}, {30, 5, -3}, {-135, 20, 40}, {250, -15, 10}}) {
    VehiclePose pose;
    pose.heading_deg = heading;
    pose.pitch_deg = pitch;
    pose.roll_deg = roll;
    Attitude attitude;
    attitude.heading_rad = heading * kDeg;
    attitude.pitch_rad = pitch * kDeg;
    attitude.roll_rad = roll * kDeg;
    EXPECT_TRUE(NedFromBody(attitude).isApprox(NedFromBody(pose), 1e-12)) << heading << " " << pitch << " " << roll;
  }
}

TEST(VelocityFilterTest, SurgeAtHeading90MovesEastNotNorth) {
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 100, 200, 10, 0.05);
  SetVelocity(&filter, Eigen::Vector3d(1, 0, 0));
  filter.PredictTo(10, Constant(Heading(90)));
  EXPECT_NEAR(filter.state()[0], 100, 1e-6);  // north
  EXPECT_NEAR(filter.state()[1], 210, 1e-6);  // east
  EXPECT_NEAR(filter.state()[2], 10, 1e-6);   // depth

  // Sway (starboard) at heading 90 is south.
  VelocityFilter sway(VelocityFilterOptions{});
  sway.Start(0, 0, 0, 10, 0.05);
  SetVelocity(&sway, Eigen::Vector3d(0, 1, 0));
  sway.PredictTo(10, Constant(Heading(90)));
  EXPECT_NEAR(sway.state()[0], -10, 1e-6);
  EXPECT_NEAR(sway.state()[1], 0, 1e-6);
}

TEST(VelocityFilterTest, SurgeWithBowUpClimbs) {
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 0, 0, 10, 0.05);
  SetVelocity(&filter, Eigen::Vector3d(1, 0, 0));
  Attitude bow_up;
  bow_up.pitch_rad = 10 * kDeg;
  filter.PredictTo(10, Constant(bow_up));
  EXPECT_NEAR(filter.state()[0], 10 * std::cos(10 * kDeg), 1e-6);
  EXPECT_NEAR(filter.state()[2], 10 - 10 * std::sin(10 * kDeg), 1e-6);  // depth decreases
}

TEST(VelocityFilterTest, PredictsInEqualStepsWithAttitudeAtMidpoints) {
  VelocityFilter filter(VelocityFilterOptions{});  // max_step_s 0.2
  filter.Start(0, 0, 0, 0, 0.05);
  std::vector<double> asked_s;
  const AttitudeAt record = [&](double time_s) {
    asked_s.push_back(time_s);
    return Attitude();
  };
  filter.PredictTo(0.5, record);  // 3 steps of 1/6 s
  filter.PredictTo(0.7, record);  // exactly one step
  filter.PredictTo(0.7, record);  // nothing to do
  const std::vector<double> expected = {1.0 / 12, 3.0 / 12, 5.0 / 12, 0.6};
  ASSERT_EQ(asked_s.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(asked_s[i], expected[i], 1e-12) << i;
  EXPECT_EQ(filter.time_s(), 0.7);
}

TEST(VelocityFilterTest, MidpointAttitudeFollowsATurn) {
  // 0.5 m/s through a 90-degree turn at 10 deg/s. With the heading of each
  // step's midpoint every step moves along the arc's chord, so the end point is
  // right to the chords' shortening (0.2 mm); a start-of-step heading lags half
  // a step (1 degree) and lands about 7 cm off.
  constexpr double kSpeed = 0.5, kRate = 10 * kDeg, kTurnS = 9;
  const double radius = kSpeed / kRate;
  const double start_heading = 20 * kDeg;
  const auto heading_at = [&](double time_s) {
    Attitude a;
    a.heading_rad = start_heading + kRate * time_s;
    return a;
  };
  const double end_heading = start_heading + kRate * kTurnS;
  const Eigen::Vector2d arc_end(radius * (std::sin(end_heading) - std::sin(start_heading)),
                                radius * (std::cos(start_heading) - std::cos(end_heading)));
  const auto fly = [&](const AttitudeAt& attitude) {
    VelocityFilter filter(VelocityFilterOptions{});
    filter.Start(0, 0, 0, 0, 0.05);
    SetVelocity(&filter, Eigen::Vector3d(kSpeed, 0, 0));
    filter.PredictTo(kTurnS, attitude);
    return Eigen::Vector2d(filter.state().head<2>());
  };
  EXPECT_LT((fly(heading_at) - arc_end).norm(), 1e-3);
  const double step_s = VelocityFilterOptions().max_step_s;
  const AttitudeAt start_of_step = [&](double time_s) { return heading_at(time_s - step_s / 2); };
  EXPECT_GT((fly(start_of_step) - arc_end).norm(), 0.05);
}

// ---------------------------------------------------------------------------
// Process noise

TEST(VelocityFilterTest, OneStepCovarianceIsTheContinuousWhiteAccelerationModel) {
  VelocityFilterOptions options;
  options.accel_density = 2e-3;
  VelocityFilter filter(options);
  filter.Start(0, 1, 2, 3, 0.3, 0.4);  // velocity 0: the attitude term vanishes
  Attitude attitude;
  attitude.heading_rad = 30 * kDeg;
  attitude.pitch_rad = 5 * kDeg;
  attitude.roll_rad = -3 * kDeg;
  filter.PredictTo(0.2, Constant(attitude));
  const Eigen::Matrix3d r = NedFromBody(attitude);
  const double q = 2e-3, dt = 0.2, sv2 = 0.16;
  const Eigen::Matrix3d i3 = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d pp0 = Eigen::Vector3d(0.09, 0.09, 0.0004).asDiagonal();
  const auto& p = filter.covariance();
  EXPECT_TRUE((p.block<3, 3>(3, 3).isApprox((sv2 + q * dt) * i3, 1e-12)));
  EXPECT_TRUE((p.block<3, 3>(0, 3).isApprox(dt * sv2 * r + q * dt * dt / 2 * r, 1e-12)));
  EXPECT_TRUE((p.block<3, 3>(3, 0).isApprox(p.block<3, 3>(0, 3).transpose(), 0)));
  EXPECT_TRUE((p.block<3, 3>(0, 0).isApprox(pp0 + dt * dt * sv2 * i3 + q * dt * dt * dt / 3 * i3, 1e-12)));
}

TEST(VelocityFilterTest, AccelerationNoiseDoesNotDependOnTheStepSize) {
  // Unlike the paper's dT * W_k: 1 s in five steps or in one gives the same P.
  Attitude attitude;
  attitude.heading_rad = 130 * kDeg;
  attitude.pitch_rad = 8 * kDeg;
  attitude.roll_rad = 4 * kDeg;
  VelocityFilterOptions fine, coarse;
  coarse.max_step_s = 1.0;
  VelocityFilter a(fine), b(coarse);
  a.Start(0, 0, 0, 0, 0.1);
  b.Start(0, 0, 0, 0, 0.1);
  a.PredictTo(1.0, Constant(attitude));
  b.PredictTo(1.0, Constant(attitude));
  EXPECT_TRUE(a.covariance().isApprox(b.covariance(), 1e-13));
}

// The attitude noise added to P_pp by one step, alone.
Eigen::Matrix3d AttitudeNoise(VelocityFilterOptions options, const Attitude& attitude,
                              const Eigen::Vector3d& velocity_mps, double step_s) {
  options.max_step_s = step_s;
  const auto predict = [&](const VelocityFilterOptions& o) {
    VelocityFilter filter(o);
    filter.Start(0, 0, 0, 0, 0.1);
    SetVelocity(&filter, velocity_mps);
    filter.PredictTo(step_s, Constant(attitude));
    return Eigen::Matrix3d(filter.covariance().topLeftCorner<3, 3>());
  };
  VelocityFilterOptions exact = options;
  exact.heading_noise_rad = 0;
  exact.pitch_noise_rad = exact.roll_noise_rad = 0.0;
  return predict(options) - predict(exact);
}

TEST(VelocityFilterTest, AttitudeNoiseAtLevelAttitudeIsTheSpecFormula) {
  VelocityFilterOptions options;
  options.roll_noise_rad = 0.01;
  options.pitch_noise_rad = 0.02;
  options.heading_noise_rad = 0.03;
  const Attitude attitude = Heading(30);
  const Eigen::Vector3d v(0.5, 0.1, 0.05);
  const double dt = 0.2;
  const Eigen::Matrix3d r = NedFromBody(attitude);
  const Eigen::Matrix3d vx = (Eigen::Matrix3d() << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0).finished();
  const Eigen::Matrix3d s_att = Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal();
  const Eigen::Matrix3d expected = dt * dt * r * vx * s_att * vx.transpose() * r.transpose();
  EXPECT_TRUE(AttitudeNoise(options, attitude, v, dt).isApprox(expected, 1e-6))
      << AttitudeNoise(options, attitude, v, dt);
}

TEST(VelocityFilterTest, AttitudeNoiseIsTheEulerAngleJacobianAtAnyAttitude) {
  // Away from level the heading turns about NED down, pitch about the
  // heading-rotated y axis, roll about the bow: check against the numerical
  // Jacobian of dT R_nb(theta) v with respect to (roll, pitch, heading).
  VelocityFilterOptions options;
  options.roll_noise_rad = 0.01;
  options.pitch_noise_rad = 0.02;
  options.heading_noise_rad = 0.03;
  Attitude attitude;
  attitude.roll_rad = -25 * kDeg;
  attitude.pitch_rad = 20 * kDeg;
  attitude.heading_rad = 130 * kDeg;
  const Eigen::Vector3d v(0.5, -0.2, 0.1);
  const double dt = 0.2, h = 1e-6;
  Eigen::Matrix3d jacobian;
  for (int axis = 0; axis < 3; ++axis) {
    Attitude plus = attitude, minus = attitude;
    double* plus_angle[] = {&plus.roll_rad, &plus.pitch_rad, &plus.heading_rad};
    double* minus_angle[] = {&minus.roll_rad, &minus.pitch_rad, &minus.heading_rad};
    *plus_angle[axis] += h;
    *minus_angle[axis] -= h;
    jacobian.col(axis) = dt * (NedFromBody(plus) - NedFromBody(minus)) * v / (2 * h);
  }
  const Eigen::Matrix3d expected = jacobian * Eigen::Vector3d(1e-4, 4e-4, 9e-4).asDiagonal() * jacobian.transpose();
  EXPECT_TRUE(AttitudeNoise(options, attitude, v, dt).isApprox(expected, 1e-5));
}

// ---------------------------------------------------------------------------
// Updates, gates, position lock-out (the survey legs: velocity_filter_survey_test.cc)

TEST(VelocityFilterTest, RejectedUpdatesLeaveStateAndCovarianceBitForBit) {
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 5, 6, 7, 0.05);
  SetVelocity(&filter, Eigen::Vector3d(0.5, 0, 0));
  filter.PredictTo(3.3, Constant(Heading(30)));
  const VelocityFilter::State x = filter.state();
  const VelocityFilter::Covariance p = filter.covariance();
  EXPECT_EQ(filter.UpdateVelocity(Eigen::Vector3d(1.5, 0, 0)), VelocityFilter::Outcome::kRejected);
  EXPECT_EQ(filter.UpdateDepth(12), VelocityFilter::Outcome::kRejected);
  EXPECT_EQ(filter.UpdatePosition(25, 6), VelocityFilter::Outcome::kRejected);
  EXPECT_GT(filter.last_nis(), VelocityFilterOptions().gate_position);
  EXPECT_TRUE(filter.state() == x);
  EXPECT_TRUE(filter.covariance() == p);
  const VelocityFilter::Counts& c = filter.counts();
  EXPECT_EQ(c.velocity_rejected + c.depth_rejected + c.position_rejected, 3);
}

TEST(VelocityFilterTest, UpdatesKeepCovarianceSymmetricPositiveDefinite) {
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 0, 0, 10, 0.05);
  Gauss gauss(3);
  Attitude attitude;
  attitude.pitch_rad = 4 * kDeg;
  attitude.roll_rad = -6 * kDeg;
  for (int k = 1; k <= 500; ++k) {
    attitude.heading_rad = 0.01 * k;
    filter.PredictTo(0.2 * k, Constant(attitude));
    filter.UpdateVelocity(Eigen::Vector3d(0.5, 0, 0) + gauss.Vector(kVoSigma));
    filter.UpdateDepth(10 + 0.02 * gauss());
    if (k % 10 == 0) filter.UpdatePosition(0.1 * k * std::cos(0.01 * k), 0.1 * k * std::sin(0.01 * k), 5.0);
  }
  const VelocityFilter::Covariance& p = filter.covariance();
  EXPECT_TRUE(p == p.transpose());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<VelocityFilter::Covariance>(p).eigenvalues().minCoeff(), 0);
}

TEST(VelocityFilterTest, PositionFixPullsThePosition) {
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 0, 0, 10, 10.0);
  EXPECT_EQ(filter.UpdatePosition(3, 4), VelocityFilter::Outcome::kAccepted);  // position_sigma_m 0.05
  EXPECT_NEAR(filter.state()[0], 3, 1e-4);
  EXPECT_NEAR(filter.state()[1], 4, 1e-4);
  EXPECT_NEAR(filter.covariance()(0, 0), 0.0025, 1e-6);
  EXPECT_EQ(filter.counts().position_accepted, 1);
}

TEST(VelocityFilterTest, LockOutReacquiresAWrongStartPosition) {
  // Started 5 m off with a claimed 5 cm: fixes every second are rejected until
  // they have agreed for lockout_position_s (10 s), then re-acquired.
  VelocityFilter filter(VelocityFilterOptions{});
  filter.Start(0, 5, -2, 10, 0.05);
  Gauss gauss(11);
  std::vector<VelocityFilter::Outcome> outcomes;
  for (int k = 1; k <= 150; ++k) {
    const double time_s = 0.2 * k;
    const Eigen::Vector3d position_m(0.5 * time_s * std::cos(30 * kDeg), 0.5 * time_s * std::sin(30 * kDeg), 10);
    filter.PredictTo(time_s, Constant(Heading(30)));
    filter.UpdateVelocity(Eigen::Vector3d(0.5, 0, 0) + gauss.Vector(kVoSigma));
    filter.UpdateDepth(10 + kDepthSigma * gauss());
    if (k % 5 == 0) {
      outcomes.push_back(filter.UpdatePosition(position_m.x() + 0.05 * gauss(), position_m.y() + 0.05 * gauss()));
    }
    if (k == 150) {
      EXPECT_LT((filter.state().head<2>() - position_m.head<2>()).norm(), 0.1);
    }
  }
  ASSERT_EQ(outcomes.size(), 30u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(outcomes[i], VelocityFilter::Outcome::kRejected) << i;  // 1 ... 10 s
  EXPECT_EQ(outcomes[10], VelocityFilter::Outcome::kReacquired);                                 // 11 s
  for (int i = 11; i < 30; ++i) EXPECT_EQ(outcomes[i], VelocityFilter::Outcome::kAccepted) << i;
  EXPECT_EQ(filter.counts().reacquisitions, 1);
  EXPECT_EQ(filter.counts().position_rejected, 10);
}

// ---------------------------------------------------------------------------
// Misuse

TEST(VelocityFilterTest, RejectsMisuse) {
  VelocityFilter filter(VelocityFilterOptions{});
  EXPECT_THROW(filter.PredictTo(1, Constant(Attitude())), std::logic_error);
  EXPECT_THROW(filter.UpdateDepth(1), std::logic_error);
  filter.Start(10, 0, 0, 0, 0.05);
  try {
    filter.PredictTo(9, Constant(Attitude()));
    ADD_FAILURE() << "time going backwards accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "time_s");
  }
  EXPECT_THROW(filter.PredictTo(NAN, Constant(Attitude())), InputError);
  EXPECT_THROW(filter.PredictTo(11, [](double) { return Heading(NAN); }), InputError);
  EXPECT_THROW(filter.UpdateVelocity(Eigen::Vector3d(NAN, 0, 0)), InputError);
  EXPECT_THROW(filter.UpdateVelocity(Eigen::Vector3d::Zero(), -Eigen::Matrix3d::Identity()), InputError);
  EXPECT_THROW(filter.UpdatePosition(0, 0, 0), InputError);
  EXPECT_THROW(filter.Start(0, 0, 0, 0, -1), InputError);
}

}  // namespace
}  // namespace seamap
