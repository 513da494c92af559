#include "core/georef/towed_fit_problem.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/georef/tether_model.h"

namespace seamap::towed_fit {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d ExpRotation(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity() + Skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

}  // namespace

double TimeSeries::At(double t) const {
  const size_t n = path_.size();
  if (n == 0) return 0;
  if (t <= path_.time(0)) return values_[0];
  if (t >= path_.time(n - 1)) return values_[n - 1];
  size_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (path_.time(mid) <= t ? lo : hi) = mid;
  }
  const double w = (t - path_.time(lo)) / (path_.time(hi) - path_.time(lo));
  return (1 - w) * values_[lo] + w * values_[hi];
}

// Fills gaps (values <= 0 or NaN) from the nearest known neighbour.
std::vector<double> Filled(const std::vector<double>& values, double fallback) {
  std::vector<double> out(values.size(), fallback);
  double last = NAN;
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i]) && values[i] > 0) last = values[i];
    out[i] = last;
  }
  double next = NAN;
  for (size_t i = values.size(); i-- > 0;) {
    if (std::isfinite(values[i]) && values[i] > 0) next = values[i];
    if (!std::isfinite(out[i])) out[i] = std::isfinite(next) ? next : fallback;
  }
  return out;
}

Problem::Problem(const SlamPath& path, const std::vector<double>& reach_m, const std::vector<double>& depth_m,
                 const BuoyTrack& buoy, const Similarity& start, double slam_sigma, const TowedFitOptions& options)
    : path_(path),
      reach_(path, Filled(reach_m, 1)),
      depth_(depth_m),
      options_(options),
      start_(start),
      slam_sigma_(slam_sigma) {
  t0_ = std::max(path.time(0), buoy.start_s());
  t1_ = std::min(path.time(path.size() - 1), buoy.end_s());
  for (const BuoyFix& f : buoy.fixes())
    if (f.time_s >= t0_ && f.time_s <= t1_) fixes_.push_back({f.time_s, f.position_en_m, std::max(f.sigma_m, 0.01)});
  centroid_.setZero();
  for (size_t i = 0; i < path.size(); ++i) centroid_ += path.position(i);
  centroid_ /= std::max<size_t>(path.size(), 1);
}

Params Problem::Initial() const {
  Params theta = Params::Zero();
  theta.segment<3>(4) = start_.Apply(centroid_);
  theta(8) = 0.5;
  return theta;
}

Model Problem::ModelAt(const Params& theta) const {
  Model m;
  m.fit.rotation = ExpRotation(theta.head<3>()) * start_.rotation;
  m.fit.scale = start_.scale * std::exp(theta(3));
  m.fit.translation = theta.segment<3>(4) - m.fit.scale * m.fit.rotation * centroid_;
  m.reach_factor = std::exp(theta(7));
  m.wake_share = theta(8);
  m.current_mps = theta.segment<2>(9);
  m.lag_s = theta(11);
  return m;
}

Simulation Problem::Simulate(const Model& m) const {
  Simulation out;
  const double step = options_.step_s;
  const int steps = std::max(2, static_cast<int>(std::ceil((t1_ - t0_) / step)) + 1);
  std::vector<Eigen::Vector2d> vehicle(steps), buoy(steps);
  std::vector<double> arc(steps, 0), reach(steps);
  std::vector<bool> taut(steps), settled(steps);
  for (int k = 0; k < steps; ++k) vehicle[k] = m.fit.Apply(path_.PositionAt(t0_ + k * step)).head<2>();
  for (int k = 1; k < steps; ++k) arc[k] = arc[k - 1] + (vehicle[k] - vehicle[k - 1]).norm();
  // The direction the vehicle started in: the buoy trails behind it.
  int ahead = 1;
  while (ahead + 1 < steps && (vehicle[ahead] - vehicle[0]).norm() < 2) ++ahead;
  Eigen::Vector2d dir0 = vehicle[ahead] - vehicle[0];
  dir0 = dir0.norm() > 1e-9 ? Eigen::Vector2d(dir0 / dir0.norm()) : Eigen::Vector2d(0, 1);
  for (int k = 0; k < steps; ++k) reach[k] = m.reach_factor * reach_.At(t0_ + k * step);
  // How far the path turns over its first reach (radians, at most 1): on
  // a straight start the buoy is where the model starts it; on a turning
  // one it may be off by that share of a reach.
  double start_doubt = 0;
  {
    int from = ahead;
    while (from + 1 < steps && arc[from] < reach[0]) ++from;
    int to = from;
    while (to + 1 < steps && (vehicle[to] - vehicle[from]).norm() < 2) ++to;
    const Eigen::Vector2d d = vehicle[to] - vehicle[from];
    if (d.norm() > 1e-9) start_doubt = std::min(std::acos(std::clamp(dir0.dot(d / d.norm()), -1.0, 1.0)), 1.0);
  }
  TowedBuoy tractrix(vehicle[0] - reach[0] * dir0);
  int back = 0;
  for (int k = 0; k < steps; ++k) {
    tractrix.Drift(m.current_mps * step);  // taut, the tether then pulls it along v - current
    tractrix.Step(vehicle[k], reach[k]);
    // The wake: reach back along the path (before the start, along the start's direction).
    const double s = arc[k] - reach[k];
    Eigen::Vector2d wake;
    if (s <= 0) {
      wake = vehicle[0] + s * dir0;
    } else {
      while (back + 1 < k && arc[back + 1] < s) ++back;
      while (back > 0 && arc[back] > s) --back;
      const double span = arc[back + 1] - arc[back];
      const double w = span > 0 ? (s - arc[back]) / span : 0;
      wake = (1 - w) * vehicle[back] + w * vehicle[back + 1];
    }
    buoy[k] = (1 - m.wake_share) * tractrix.position() + m.wake_share * wake;
    taut[k] = (vehicle[k] - buoy[k]).norm() >= 0.98 * reach[k];
    settled[k] = arc[k] >= options_.settle_reaches * reach[k];
  }
  auto at = [&](double t) { return std::clamp(static_cast<int>(std::lround((t - t0_) / step)), 0, steps - 1); };
  for (const Fix& f : fixes_) {
    const double x = (f.time_s - m.lag_s - t0_) / step;
    const int k = std::clamp(static_cast<int>(std::floor(x)), 0, steps - 2);
    const double w = std::clamp(x - k, 0.0, 1.0);
    out.buoy.push_back((1 - w) * buoy[k] + w * buoy[k + 1]);
    const int n = at(f.time_s - m.lag_s);
    const Eigen::Vector2d d = vehicle[n] - buoy[n];
    out.towing.push_back(d.norm() > 1e-9 ? Eigen::Vector2d(d / d.norm()) : dir0);
    out.taut.push_back(taut[n]);
    out.settled.push_back(settled[n]);
    // The buoy starts a reach behind along the path's first 2 m, which is
    // not where it was where the path turns: on a spiral begun in a tight
    // turn, 1.7 m aside. A towed buoy forgets its start as exp(-travel /
    // reach), so its fixes get that much of the start's doubt as noise
    // until settled. The scatter of the settling fixes showed the misfit
    // without GPS noise (0.5 m) but not under it, and they pulled the
    // reach 3-5 % short (docs/GEOREF.md, "seventh pass").
    out.start_sigma_m.push_back(settled[n] ? 0.0
                                           : start_doubt * reach[n] * std::exp(-arc[n] / std::max(reach[n], 1e-9)));
  }
  for (size_t i = 0; i < path_.size(); ++i) {
    const double t = path_.time(i);
    const int n = at(t);
    out.keyframe_taut.push_back(t >= t0_ && t <= t1_ && taut[n] && settled[n]);
  }
  return out;
}

Eigen::VectorXd Problem::Residuals(const Params& theta, Simulation* sim) const {
  const Model m = ModelAt(theta);
  Simulation s = Simulate(m);
  Eigen::VectorXd r(2 * fixes_.size() + depth_count());
  for (size_t j = 0; j < fixes_.size(); ++j) r.segment<2>(2 * j) = fixes_[j].position - s.buoy[j];
  size_t row = 2 * fixes_.size();
  for (size_t i = 0; i < path_.size(); ++i)
    if (std::isfinite(depth_[i])) r(row++) = -depth_[i] - m.fit.Apply(path_.position(i)).z();
  if (sim) *sim = std::move(s);
  return r;
}

size_t Problem::depth_count() const {
  return static_cast<size_t>(std::count_if(depth_.begin(), depth_.end(), [](double d) { return std::isfinite(d); }));
}

Eigen::MatrixXd Problem::Jacobian(const Params& theta) const {
  static const double kStep[kParams] = {1e-5, 1e-5, 1e-5, 1e-5, 1e-3, 1e-3, 1e-3, 1e-4, 1e-3, 1e-4, 1e-4, 1e-3};
  Eigen::MatrixXd j(2 * fixes_.size() + depth_count(), kParams);
  for (int p = 0; p < kParams; ++p) {
    Params plus = theta, minus = theta;
    plus(p) += kStep[p];
    minus(p) -= kStep[p];
    j.col(p) = (Residuals(plus) - Residuals(minus)) / (2 * kStep[p]);
  }
  return j;
}

Eigen::Matrix<double, 2, kParams> Problem::KeyframeJacobian(const Model& m, const Eigen::Vector3d& slam) const {
  const Eigen::Vector3d p = m.fit.scale * m.fit.rotation * (slam - centroid_);
  Eigen::Matrix<double, 3, kParams> j = Eigen::Matrix<double, 3, kParams>::Zero();
  j.block<3, 3>(0, 0) = -Skew(p);
  j.col(3) = p;
  j.block<3, 3>(0, 4) = Eigen::Matrix3d::Identity();
  return j.topRows<2>();
}

// The priors: log k, the current and the lag about 0, the wake share about its mean.
ParamMatrix PriorInformation(const TowedFitOptions& o) {
  ParamMatrix p = ParamMatrix::Zero();
  p(7, 7) = 1 / (o.reach_prior_sigma * o.reach_prior_sigma);
  p(8, 8) = 1 / (o.wake_prior_sigma * o.wake_prior_sigma);
  p(9, 9) = p(10, 10) = 1 / (o.current_prior_mps * o.current_prior_mps);
  p(11, 11) = 1 / (o.lag_prior_s * o.lag_prior_s);
  return p;
}

Params PriorOffset(const Params& theta, const TowedFitOptions& o) {
  Params d = Params::Zero();
  d.tail<kParams - 7>() = theta.tail<kParams - 7>();  // log k, wake share, current, lag
  d(8) -= o.wake_prior_mean;
  return d;
}

}  // namespace seamap::towed_fit
