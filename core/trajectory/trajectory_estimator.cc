#include "core/trajectory/trajectory_estimator.h"

#include <cmath>

#include "core/trajectory/ground_offsets.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180;

Attitude AttitudeOf(const VehiclePose& p) {
  return {p.roll_deg * kDegToRad, p.pitch_deg * kDegToRad, p.heading_deg * kDegToRad};
}

}  // namespace

EstimatorMode ParseEstimatorMode(const std::string& text, const std::string& option) {
  if (text == "vo") return EstimatorMode::kVo;
  if (text == "ekf") return EstimatorMode::kEkf;
  throw InputError("", 0, option, "expected vo or ekf, got '" + text + "'");
}

void EstimatorOptions::Check() const {
  if (!(nav_sigma_m > 0) || !std::isfinite(nav_sigma_m)) throw InputError("", 0, "--nav-noise", "expected metres > 0");
  if (!(max_gap_s > 0) || !std::isfinite(max_gap_s)) throw InputError("", 0, "max_gap_s", "expected seconds > 0");
  vo.Check();
  filter.Check();
}

TrajectoryEstimator::TrajectoryEstimator(const CameraModel& camera, const EstimatorOptions& options)
    : camera_(camera),
      options_(options),
      vo_(camera, options.vo, options.filter.vo_sigma_mps),
      filter_(options.filter) {
  options_.Check();
}

VehiclePose TrajectoryEstimator::Add(const FrameFeatures* features, double time_s, const VehiclePose& nav) {
  ++frames_;
  last_flags_.clear();
  const Attitude attitude = AttitudeOf(nav);
  const bool gap = filter_.started() && time_s - filter_.time_s() > options_.max_gap_s;
  if (gap) {
    // Across a gap nothing is known of the motion: start again from the
    // navigation (and a fresh visual odometry reference), as at the first frame.
    gaps_.emplace_back(time_s, time_s - filter_.time_s());
    last_flags_ = "restart_after_gap";
    vo_.Restart();
  }
  if (!filter_.started() || gap) {
    filter_.Start(time_s, nav.north_m, nav.east_m, nav.depth_m, options_.nav_sigma_m);
  } else if (time_s > filter_.time_s()) {
    // The attitude between two frames, interpolated (heading on the circle).
    const double t0 = last_time_s_, t1 = time_s;
    const Attitude a0 = last_attitude_, a1 = attitude;
    filter_.PredictTo(time_s, [=](double t) {
      const double f = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
      return Attitude{a0.roll_rad + f * (a1.roll_rad - a0.roll_rad), a0.pitch_rad + f * (a1.pitch_rad - a0.pitch_rad),
                      a0.heading_rad + f * WrapAngle(a1.heading_rad - a0.heading_rad)};
    });
  }
  last_time_s_ = time_s;
  last_attitude_ = attitude;
  if (features) {
    const int low_texture = vo_.counts().low_texture, identical = vo_.counts().identical;
    if (auto m = vo_.Add(*features, time_s, nav)) filter_.UpdateVelocity(m->body_velocity_mps, m->covariance);
    if (vo_.counts().identical > identical)
      last_flags_ += (last_flags_.empty() ? "" : ";") + std::string("identical_photos");
    if (vo_.counts().low_texture > low_texture)
      last_flags_ += (last_flags_.empty() ? "" : ";") + std::string("low_texture");
  }
  if (std::isfinite(nav.depth_m)) filter_.UpdateDepth(nav.depth_m);
  if (options_.mode == EstimatorMode::kEkf && frames_ > 1)
    filter_.UpdatePosition(nav.north_m, nav.east_m, options_.nav_sigma_m);
  VehiclePose out = nav;
  out.north_m = filter_.state()(0);
  out.east_m = filter_.state()(1);
  out.depth_m = filter_.state()(2);
  return out;
}

}  // namespace seamap
