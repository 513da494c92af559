#include "core/trajectory/velocity_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "core/geo/rotation.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

constexpr int kPos = 0;  // first index of (n, e, d) in the state
constexpr int kVel = 3;  // first index of (u, v, w)

// Lock-out recovery resets the velocity block to this variance, (m/s)^2 ...
constexpr double kReacquireVelocityVariance = 1.0;
// ... and the horizontal position block to this multiple of the fix's variance.
constexpr double kReacquirePositionFactor = 100.0;
// Rejected innovations agree when each lies within this many sigma of their median.
constexpr double kAgreeSigmas = 3.0;

std::string Text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void Require(bool ok, const char* field, const std::string& expected, double value) {
  if (!ok) throw InputError("", 0, field, "expected " + expected + ", got " + Text(value));
}

void RequirePositive(const char* field, double value) {
  Require(std::isfinite(value) && value > 0, field, "a finite number > 0", value);
}

void RequireFinite(const char* field, double value) {
  Require(std::isfinite(value), field, "a finite number", value);
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

}  // namespace

Eigen::Matrix3d NedFromBody(const Attitude& attitude) {
  return RotationZyx(attitude.heading_rad, attitude.pitch_rad, attitude.roll_rad);
}

void VelocityFilterOptions::Check() const {
  RequirePositive("accel_density", accel_density);
  Require(std::isfinite(heading_noise_rad) && heading_noise_rad >= 0, "heading_noise_rad", "a finite number >= 0",
          heading_noise_rad);
  if (pitch_noise_rad) {
    Require(std::isfinite(*pitch_noise_rad) && *pitch_noise_rad >= 0, "pitch_noise_rad", "a finite number >= 0",
            *pitch_noise_rad);
  }
  if (roll_noise_rad) {
    Require(std::isfinite(*roll_noise_rad) && *roll_noise_rad >= 0, "roll_noise_rad", "a finite number >= 0",
            *roll_noise_rad);
  }
  for (int i = 0; i < 3; ++i) RequirePositive("vo_sigma_mps", vo_sigma_mps[i]);
  RequirePositive("depth_sigma_m", depth_sigma_m);
  RequirePositive("position_sigma_m", position_sigma_m);
  RequirePositive("max_step_s", max_step_s);
  RequirePositive("gate_velocity", gate_velocity);
  RequirePositive("gate_depth", gate_depth);
  RequirePositive("gate_position", gate_position);
  // One rejection is no evidence of a lock-out: a single outlier would re-acquire.
  Require(lockout_velocity_count >= 2, "lockout_velocity_count", "an integer >= 2", lockout_velocity_count);
  RequirePositive("lockout_position_s", lockout_position_s);
}

VelocityFilter::VelocityFilter(const VelocityFilterOptions& options) : options_(options) {
  options_.Check();
}

void VelocityFilter::Start(double time_s, double north_m, double east_m, double depth_m, double position_sigma_m,
                           double velocity_sigma_mps) {
  RequireFinite("time_s", time_s);
  RequireFinite("north_m", north_m);
  RequireFinite("east_m", east_m);
  RequireFinite("depth_m", depth_m);
  RequirePositive("position_sigma_m", position_sigma_m);
  RequirePositive("velocity_sigma_mps", velocity_sigma_mps);
  if (!started_) counts_ = Counts();  // a restart keeps counting
  started_ = true;
  time_s_ = time_s;
  x_ << north_m, east_m, depth_m, 0, 0, 0;
  const double sp2 = position_sigma_m * position_sigma_m;
  const double sv2 = velocity_sigma_mps * velocity_sigma_mps;
  p_ = State(sp2, sp2, options_.depth_sigma_m * options_.depth_sigma_m, sv2, sv2, sv2).asDiagonal();
  last_nis_ = 0;
  velocity_rejections_.clear();
  position_rejections_.clear();
}

void VelocityFilter::RequireStarted() const {
  if (!started_) throw std::logic_error("VelocityFilter: Start() must come before predictions and updates");
}

void VelocityFilter::PredictTo(double time_s, const AttitudeAt& attitude) {
  RequireStarted();
  Require(time_s >= time_s_, "time_s", "a time >= the filter's " + Text(time_s_), time_s);  // also rejects NaN
  if (time_s == time_s_) return;
  const double span_s = time_s - time_s_;
  // Step by step across a day would take minutes (and overflow the count
  // across 1e10 s): callers restart the filter across gaps (trajectory_estimator.h).
  constexpr double kMaxSpanS = 86400;
  Require(span_s <= kMaxSpanS, "time_s", "at most " + Text(kMaxSpanS) + " s after the filter's " + Text(time_s_),
          time_s);
  // The tolerance keeps a span of exactly max_step_s, give or take rounding, in one step.
  const int steps = std::max(1, static_cast<int>(std::ceil(span_s / options_.max_step_s - 1e-9)));
  const double step_s = span_s / steps;
  const double start_s = time_s_;
  for (int k = 0; k < steps; ++k) Predict(step_s, attitude(start_s + (k + 0.5) * step_s));
  time_s_ = time_s;
}

void VelocityFilter::Predict(double step_s, const Attitude& attitude) {
  const Eigen::Matrix3d ned_from_body = NedFromBody(attitude);
  if (!ned_from_body.allFinite()) throw InputError("", 0, "attitude", "expected finite angles, got NaN or infinity");
  const Eigen::Vector3d velocity_ned_mps = ned_from_body * x_.segment<3>(kVel);
  x_.segment<3>(kPos) += step_s * velocity_ned_mps;

  Covariance f = Covariance::Identity();
  f.block<3, 3>(kPos, kVel) = step_s * ned_from_body;

  // Continuous white acceleration of density q on each body axis, integrated
  // exactly over the step (attitude held at the midpoint value).
  const double q = options_.accel_density;
  const double dt = step_s;
  Covariance noise = Covariance::Zero();
  noise.block<3, 3>(kVel, kVel) = q * dt * Eigen::Matrix3d::Identity();
  noise.block<3, 3>(kPos, kVel) = q * dt * dt / 2 * ned_from_body;
  noise.block<3, 3>(kVel, kPos) = noise.block<3, 3>(kPos, kVel).transpose();
  noise.block<3, 3>(kPos, kPos) = q * dt * dt * dt / 3 * Eigen::Matrix3d::Identity();

  // Attitude noise into position: an Euler-angle error delta rotates the NED
  // velocity by eps = J delta, J = [R_nb e_x, Rz(heading) e_y, e_z] (the axes
  // roll, pitch and heading turn about), so dp = -dT [R_nb v]x J delta. At level
  // attitude J = R_nb and this is the spec's dT^2 R_nb [v]x S_att [v]x^T R_nb^T.
  // Like the spec's term it is white per step, so it scales with the step length.
  const double sh = options_.heading_noise_rad;
  const double sp = options_.pitch_noise_rad.value_or(sh);
  const double sr = options_.roll_noise_rad.value_or(sh);
  const double heading = attitude.heading_rad;
  Eigen::Matrix3d axes;
  axes.col(0) = ned_from_body.col(0);
  axes.col(1) = Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0);
  axes.col(2) = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3d g = dt * Skew(velocity_ned_mps) * axes;
  noise.block<3, 3>(kPos, kPos) += g * Eigen::Vector3d(sr * sr, sp * sp, sh * sh).asDiagonal() * g.transpose();

  p_ = f * p_ * f.transpose() + noise;
  p_ = 0.5 * (p_ + p_.transpose()).eval();
}

VelocityFilter::Outcome VelocityFilter::UpdateVelocity(const Eigen::Vector3d& body_velocity_mps,
                                                       const Eigen::Matrix3d& covariance) {
  RequireStarted();
  for (int i = 0; i < 3; ++i) RequireFinite("body_velocity_mps", body_velocity_mps[i]);
  if (!covariance.allFinite()) throw InputError("", 0, "covariance", "expected finite entries");
  Eigen::Matrix<double, 3, 6> h = Eigen::Matrix<double, 3, 6>::Zero();
  h.block<3, 3>(0, kVel).setIdentity();
  return Update<3>(Kind::kVelocity, h, body_velocity_mps, covariance);
}

VelocityFilter::Outcome VelocityFilter::UpdateVelocity(const Eigen::Vector3d& body_velocity_mps) {
  return UpdateVelocity(body_velocity_mps, options_.vo_sigma_mps.cwiseAbs2().asDiagonal().toDenseMatrix());
}

VelocityFilter::Outcome VelocityFilter::UpdateDepth(double depth_m) {
  RequireStarted();
  RequireFinite("depth_m", depth_m);
  Eigen::Matrix<double, 1, 6> h = Eigen::Matrix<double, 1, 6>::Zero();
  h(0, kPos + 2) = 1;
  const double r = options_.depth_sigma_m * options_.depth_sigma_m;
  return Update<1>(Kind::kDepth, h, Eigen::Matrix<double, 1, 1>(depth_m), Eigen::Matrix<double, 1, 1>(r));
}

VelocityFilter::Outcome VelocityFilter::UpdatePosition(double north_m, double east_m, double sigma_m) {
  RequireStarted();
  RequireFinite("north_m", north_m);
  RequireFinite("east_m", east_m);
  RequirePositive("sigma_m", sigma_m);
  Eigen::Matrix<double, 2, 6> h = Eigen::Matrix<double, 2, 6>::Zero();
  h.block<2, 2>(0, kPos).setIdentity();
  const Eigen::Matrix2d r = sigma_m * sigma_m * Eigen::Matrix2d::Identity();
  return Update<2>(Kind::kPosition, h, Eigen::Vector2d(north_m, east_m), r);
}

VelocityFilter::Outcome VelocityFilter::UpdatePosition(double north_m, double east_m) {
  return UpdatePosition(north_m, east_m, options_.position_sigma_m);
}

template <int M>
VelocityFilter::Outcome VelocityFilter::Update(Kind kind, const Eigen::Matrix<double, M, 6>& h,
                                               const Eigen::Matrix<double, M, 1>& z,
                                               const Eigen::Matrix<double, M, M>& r) {
  using MatrixM = Eigen::Matrix<double, M, M>;
  const Eigen::Matrix<double, M, 1> innovation = z - h * x_;
  const MatrixM s = h * p_ * h.transpose() + r;
  const Eigen::LLT<MatrixM> llt(s);
  if (llt.info() != Eigen::Success) throw InputError("", 0, "covariance", "expected a positive definite covariance");
  const double nis = innovation.dot(llt.solve(innovation));
  last_nis_ = nis;

  const double gate = kind == Kind::kVelocity ? options_.gate_velocity
                      : kind == Kind::kDepth  ? options_.gate_depth
                                              : options_.gate_position;
  if (nis <= gate) {
    Apply<M>(h, innovation, r, s);
    switch (kind) {
      case Kind::kVelocity:
        ++counts_.velocity_accepted;
        counts_.velocity_nis_sum += nis;
        velocity_rejections_.clear();
        break;
      case Kind::kDepth:
        ++counts_.depth_accepted;
        break;
      case Kind::kPosition:
        ++counts_.position_accepted;
        position_rejections_.clear();
        break;
    }
    return Outcome::kAccepted;
  }

  if (kind != Kind::kDepth) {
    Rejection rejection{time_s_, Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()};
    rejection.innovation.head<M>() = innovation;
    rejection.sigma.head<M>() = s.diagonal().cwiseSqrt();
    if (LockedOut(kind, rejection)) {
      // The filter is wrong, not the sensor: forget the block's history and
      // take this measurement as it comes.
      if (kind == Kind::kVelocity) {
        ResetBlock(kVel, 3, kReacquireVelocityVariance);
      } else {
        ResetBlock(kPos, 2, kReacquirePositionFactor * r.diagonal().maxCoeff());
      }
      const Eigen::Matrix<double, M, 1> fresh_innovation = z - h * x_;
      Apply<M>(h, fresh_innovation, r, h * p_ * h.transpose() + r);
      ++counts_.reacquisitions;
      return Outcome::kReacquired;
    }
  }
  switch (kind) {
    case Kind::kVelocity:
      ++counts_.velocity_rejected;
      break;
    case Kind::kDepth:
      ++counts_.depth_rejected;
      break;
    case Kind::kPosition:
      ++counts_.position_rejected;
      break;
  }
  return Outcome::kRejected;
}

template <int M>
void VelocityFilter::Apply(const Eigen::Matrix<double, M, 6>& h, const Eigen::Matrix<double, M, 1>& innovation,
                           const Eigen::Matrix<double, M, M>& r, const Eigen::Matrix<double, M, M>& s) {
  // K = P H^T S^-1, through the Cholesky factor of S (symmetric positive definite).
  const Eigen::Matrix<double, 6, M> gain = s.llt().solve(h * p_).transpose();
  x_ += gain * innovation;
  // Joseph form: stays symmetric positive semi-definite in floating point.
  const Covariance i_kh = Covariance::Identity() - gain * h;
  p_ = i_kh * p_ * i_kh.transpose() + gain * r * gain.transpose();
  p_ = 0.5 * (p_ + p_.transpose()).eval();
}

bool VelocityFilter::LockedOut(Kind kind, const Rejection& rejection) {
  const bool velocity = kind == Kind::kVelocity;
  std::deque<Rejection>& rejections = velocity ? velocity_rejections_ : position_rejections_;
  const int dims = velocity ? 3 : 2;
  rejections.push_back(rejection);

  // Drop the oldest until the rest agree: each innovation within 3 sigma (its
  // own sqrt(diag S)) of the per-axis median. Innovations, not raw
  // measurements, so that positions of a moving vehicle can agree.
  auto agree = [&] {
    for (int axis = 0; axis < dims; ++axis) {
      std::vector<double> values;
      for (const Rejection& r : rejections) values.push_back(r.innovation[axis]);
      const double median = Percentile(values, 0.5);  // the mean of the middle pair
      for (const Rejection& r : rejections) {
        if (std::abs(r.innovation[axis] - median) > kAgreeSigmas * r.sigma[axis]) return false;
      }
    }
    return true;
  };
  while (rejections.size() > 1 && !agree()) rejections.pop_front();

  const bool locked = velocity ? static_cast<int>(rejections.size()) >= options_.lockout_velocity_count
                               : rejections.size() > 1 && rejections.back().time_s - rejections.front().time_s >=
                                                              options_.lockout_position_s;
  if (locked) rejections.clear();
  return locked;
}

void VelocityFilter::ResetBlock(int first, int size, double min_variance) {
  // Cross-covariances of a wrong estimate mean nothing: zero them. Keeping the
  // diagonal of the rest leaves P positive semi-definite.
  for (int i = first; i < first + size; ++i) {
    const double variance = std::max(p_(i, i), min_variance);
    p_.row(i).setZero();
    p_.col(i).setZero();
    p_(i, i) = variance;
  }
}

}  // namespace seamap
