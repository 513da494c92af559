#pragma once
// Simulated survey legs for the VelocityFilter tests: truth, VO and depth
// measurements with seeded noise that is the same on every standard library.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include <Eigen/Cholesky>

#include "core/trajectory/velocity_filter.h"

namespace seamap::testing {

inline constexpr double kDeg = M_PI / 180.0;
inline const Eigen::Vector3d kVoSigma(0.059, 0.043, 0.029);  // seed 003 Table 2
inline constexpr double kDepthSigma = 0.02;

// Gaussian draws that are the same on every standard library (std::normal_distribution is not).
class Gauss {
 public:
  explicit Gauss(uint64_t seed) : engine_(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
  }
  Eigen::Vector3d Vector(const Eigen::Vector3d& sigma) {
    const double x = (*this)(), y = (*this)(), z = (*this)();
    return Eigen::Vector3d(x, y, z).cwiseProduct(sigma);
  }

 private:
  std::mt19937_64 engine_;
};

inline AttitudeAt Constant(const Attitude& attitude) {
  return [attitude](double) { return attitude; };
}

inline Attitude Heading(double heading_deg) {
  Attitude a;
  a.heading_rad = heading_deg * kDeg;
  return a;
}

// Sets the velocity state to `velocity_mps`, practically exactly.
inline void SetVelocity(VelocityFilter* filter, const Eigen::Vector3d& velocity_mps) {
  ASSERT_EQ(filter->UpdateVelocity(velocity_mps, 1e-14 * Eigen::Matrix3d::Identity()),
            VelocityFilter::Outcome::kAccepted);
}

inline double PositionNees(const VelocityFilter& filter, const Eigen::Vector3d& true_position_m) {
  const Eigen::Vector3d error = true_position_m - filter.state().head<3>();
  return error.dot(filter.covariance().topLeftCorner<3, 3>().llt().solve(error));
}

// ---------------------------------------------------------------------------
// The constant-velocity survey leg of spec test 5: u = 0.5 m/s, heading 30,
// VO and depth every 0.2 s. `tamper` may alter step k's measurements or skip
// them; the noise is drawn the same either way, so runs differ only there.

struct Measurements {
  Eigen::Vector3d vo_mps;
  double depth_m;
  bool use_vo = true;
  bool use_depth = true;
};

struct LegResult {
  Eigen::Matrix<double, 6, 1> final_state;
  double velocity_rms_mps = 0;  // 3-D error norm, after the first minute
  Eigen::Vector3d velocity_rms_axis_mps = Eigen::Vector3d::Zero();
  double final_position_nees = 0;
  VelocityFilter::Counts counts;
  std::vector<VelocityFilter::Outcome> vo_outcomes;
  std::vector<VelocityFilter::Outcome> depth_outcomes;
  std::vector<double> times_s;
  std::vector<Eigen::Vector3d> velocity_errors_mps;  // estimate - truth after each step's updates
};

inline LegResult FlyConstantVelocityLeg(const VelocityFilterOptions& options, uint64_t seed,
                                        const std::function<void(int, Measurements*)>& tamper = {},
                                        const std::function<Eigen::Vector3d(double)>& true_velocity_at = {}) {
  constexpr int kSteps = 3000;
  constexpr double kStepS = 0.2;
  const Attitude attitude = Heading(30);
  const Eigen::Matrix3d ned_from_body = NedFromBody(attitude);
  Gauss gauss(seed);
  VelocityFilter filter(options);
  Eigen::Vector3d position_m(0, 0, 20);
  filter.Start(0, position_m.x(), position_m.y(), position_m.z(), 0.05);

  LegResult result;
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  int counted = 0;
  for (int k = 1; k <= kSteps; ++k) {
    const double time_s = k * kStepS;
    const Eigen::Vector3d velocity_mps =
        true_velocity_at ? true_velocity_at(time_s - kStepS / 2) : Eigen::Vector3d(0.5, 0, 0);
    position_m += kStepS * ned_from_body * velocity_mps;
    Measurements m;
    m.vo_mps = velocity_mps + gauss.Vector(kVoSigma);
    m.depth_m = position_m.z() + kDepthSigma * gauss();
    if (tamper) tamper(k, &m);

    filter.PredictTo(time_s, Constant(attitude));
    if (m.use_vo) result.vo_outcomes.push_back(filter.UpdateVelocity(m.vo_mps));
    if (m.use_depth) result.depth_outcomes.push_back(filter.UpdateDepth(m.depth_m));
    result.times_s.push_back(time_s);
    result.velocity_errors_mps.push_back(filter.state().tail<3>() - velocity_mps);
    if (time_s > 60) {
      sum_sq += (filter.state().tail<3>() - velocity_mps).cwiseAbs2();
      ++counted;
    }
  }
  result.final_state = filter.state();
  result.velocity_rms_axis_mps = (sum_sq / counted).cwiseSqrt();
  result.velocity_rms_mps = std::sqrt(sum_sq.sum() / counted);
  result.final_position_nees = PositionNees(filter, position_m);
  result.counts = filter.counts();
  return result;
}

}  // namespace seamap::testing
