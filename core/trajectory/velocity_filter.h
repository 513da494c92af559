#pragma once
// The navigation filter of the visual-odometry trajectory (seed 003; spec
// "Visual odometry + EKF", section 2.5). State
// x = [n, e, d, u, v, w]: NED position in metres and body-frame velocity in m/s.
// Attitude (roll, pitch, heading) is an input, not a state, so the model is
// linear: a Kalman filter with time-varying matrices, F = [[I, dT R_nb], [0, I]].
//
// Measurements: VO body velocity, pressure depth, horizontal position fixes.
// Each is gated on its innovation (chi-square on S = H P H^T + R); a rejected
// one leaves state and covariance untouched. Consecutive rejections that agree
// with one another mean the filter, not the sensor, is wrong: the filter then
// re-acquires (lock-out recovery).
#include <deque>
#include <functional>
#include <optional>

#include <Eigen/Core>

namespace seamap {

// Radians; R_nb = Rz(heading) Ry(pitch) Rx(roll) (core/geo/rotation.h).
struct Attitude {
  double roll_rad = 0;     // starboard down positive
  double pitch_rad = 0;    // bow up positive
  double heading_rad = 0;  // clockwise from north
};

// The vehicle's attitude at a time (interpolated by the caller, heading on the circle).
using AttitudeAt = std::function<Attitude(double time_s)>;

// Rotation taking body vectors (x bow, y starboard, z down) to NED: RotationZyx of the attitude.
Eigen::Matrix3d NedFromBody(const Attitude& attitude);

struct VelocityFilterOptions {
  double accel_density = 1e-3;                        // q, m^2/s^3, white acceleration on each body axis
  double heading_noise_rad = 0.0175;                  // AHRS noise into position (S_att), white per step
  std::optional<double> pitch_noise_rad;              // heading_noise_rad when unset
  std::optional<double> roll_noise_rad;               // heading_noise_rad when unset
  Eigen::Vector3d vo_sigma_mps{0.059, 0.043, 0.029};  // seed 003 Table 2, VO std per body axis
  double depth_sigma_m = 0.02;
  double position_sigma_m = 0.05;  // navigation fixes ("ekf" mode)
  double max_step_s = 0.2;         // prediction steps at most this long
  // Chi-square 1 % for 3, 1 and 2 degrees of freedom.
  double gate_velocity = 11.34;
  double gate_depth = 6.63;
  double gate_position = 9.21;
  int lockout_velocity_count = 5;  // consecutive rejected VO updates that agree => re-acquire
  double lockout_position_s = 10;  // seconds of rejected positions that agree => re-acquire

  // Throws InputError whose field() names the first bad option.
  void Check() const;
};

class VelocityFilter {
 public:
  using State = Eigen::Matrix<double, 6, 1>;
  using Covariance = Eigen::Matrix<double, 6, 6>;

  enum class Outcome { kAccepted, kRejected, kReacquired };

  struct Counts {
    int velocity_accepted = 0;
    int velocity_rejected = 0;
    int depth_accepted = 0;
    int depth_rejected = 0;
    int position_accepted = 0;
    int position_rejected = 0;
    int reacquisitions = 0;       // velocity and position together
    double velocity_nis_sum = 0;  // over accepted VO updates only
  };

  // Throws InputError on bad options (VelocityFilterOptions::Check).
  explicit VelocityFilter(const VelocityFilterOptions& options);

  // First fix: position with its sigma, depth with depth_sigma_m, velocity 0
  // with velocity_sigma_mps on each axis. May be called again to restart
  // (the counts go on).
  void Start(double time_s, double north_m, double east_m, double depth_m, double position_sigma_m,
             double velocity_sigma_mps = 0.5);

  // Predicts to time_s (>= time_s() and at most a day later, else InputError) in equal steps of at most
  // max_step_s, with the attitude at each step's midpoint: a start-of-step
  // attitude lags in turns. Before Start(), this and the updates throw
  // std::logic_error.
  void PredictTo(double time_s, const AttitudeAt& attitude);

  // Measurements at the filter's current time (PredictTo first); InputError on
  // non-finite values. A rejected update leaves state and covariance untouched
  // bit for bit. Lock-out (velocity and position, not depth): rejected
  // innovations that agree (each within 3 sigma of their per-axis median, sigma
  // from diag S) over lockout_velocity_count updates, or over
  // lockout_position_s seconds, re-acquire on the measurement that completes
  // the evidence: the block of P is reset (velocity variance >= 1 (m/s)^2,
  // horizontal position >= 100 sigma_m^2, cross-covariances zeroed) and that
  // measurement applied ungated; it returns kReacquired and counts only in
  // reacquisitions.
  Outcome UpdateVelocity(const Eigen::Vector3d& body_velocity_mps, const Eigen::Matrix3d& covariance);
  Outcome UpdateVelocity(const Eigen::Vector3d& body_velocity_mps);  // diag(vo_sigma_mps^2)
  Outcome UpdateDepth(double depth_m);
  Outcome UpdatePosition(double north_m, double east_m, double sigma_m);
  Outcome UpdatePosition(double north_m, double east_m);  // position_sigma_m

  bool started() const { return started_; }
  double time_s() const { return time_s_; }
  const State& state() const { return x_; }
  const Covariance& covariance() const { return p_; }
  // Mean VO NIS = velocity_nis_sum / velocity_accepted: 3 without gates; a
  // consistent filter behind the 1 % gate gives about 2.91 (truncation alone 2.89).
  const Counts& counts() const { return counts_; }
  // Normalised innovation squared of the last update of any kind, accepted
  // or not (before any lock-out reset): for NIS histograms.
  double last_nis() const { return last_nis_; }

 private:
  // A rejected innovation with its per-axis sigma, sqrt(diag S).
  struct Rejection {
    double time_s;
    Eigen::Vector3d innovation;
    Eigen::Vector3d sigma;
  };

  enum class Kind { kVelocity, kDepth, kPosition };

  template <int M>
  Outcome Update(Kind kind, const Eigen::Matrix<double, M, 6>& h, const Eigen::Matrix<double, M, 1>& z,
                 const Eigen::Matrix<double, M, M>& r);
  template <int M>
  void Apply(const Eigen::Matrix<double, M, 6>& h, const Eigen::Matrix<double, M, 1>& innovation,
             const Eigen::Matrix<double, M, M>& r, const Eigen::Matrix<double, M, M>& s);
  // Records a rejection; true when the rejections now prove a lock-out.
  bool LockedOut(Kind kind, const Rejection& rejection);
  void ResetBlock(int first, int size, double min_variance);
  void Predict(double step_s, const Attitude& attitude);
  void RequireStarted() const;

  VelocityFilterOptions options_;
  bool started_ = false;
  double time_s_ = 0;
  State x_ = State::Zero();
  Covariance p_ = Covariance::Zero();
  Counts counts_;
  double last_nis_ = 0;
  std::deque<Rejection> velocity_rejections_;  // consecutive, newest last
  std::deque<Rejection> position_rejections_;
};

}  // namespace seamap
