#include "core/georef/taut_selection.h"

#include <algorithm>
#include <cmath>

#include "core/georef/tether.h"
#include "core/georef/tether_model.h"

namespace seamap {
namespace {

constexpr double kDeg = M_PI / 180.0;

double AngleRad(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(std::fabs(a.x() * b.y() - a.y() * b.x()), a.dot(b));
}

// The window of fixes that pins the towing direction (tether.h), at least a
// few fixes for a quadratic, at most two minutes.
double WindowFor(const SubmapContext& c, size_t i, int leg) {
  const double rate = c.buoy.fix_rate_hz();
  const double speed = std::max(c.leg_speed_mps[leg], c.options.min_buoy_speed_mps);
  const double window = DirectionWindow(c.buoy.sigma_m(), speed, rate, c.reach_m[i]);
  return std::clamp(window, std::max(4.0, 5.0 / rate), 120.0);
}

TargetSet EmptySet(size_t n) {
  TargetSet s;
  s.reason.assign(n, "");
  s.target_enu_m.assign(n, Eigen::Vector3d::Zero());
  s.towing.assign(n, Eigen::Vector2d::Zero());
  s.sigma_m.assign(n, 0);
  s.gps_sigma_m.assign(n, 0);
  return s;
}

// The target's horizontal variance per axis: GPS, reach error from a depth
// error (it grows as the tether steepens), direction error, SLAM noise.
double TargetVariance(const SubmapContext& c, size_t i, double gps_sigma, double direction_sigma_rad, double scale) {
  const double depth = c.depth_m[i].value_or(0), reach = std::max(c.reach_m[i], 1e-6);
  const double depth_sigma = std::max(c.options.depth_sigma_m, 0.0);
  const double reach_sigma = depth / reach * depth_sigma;
  const double slam_sigma = scale * c.path.NoiseSigma();
  return gps_sigma * gps_sigma + reach_sigma * reach_sigma + std::pow(reach * direction_sigma_rad, 2) +
         slam_sigma * slam_sigma;
}

// The buoy's position at t from the two fixes around it (each fix's error
// enters once per pair, not smoothed across a window that may bend).
Eigen::Vector2d InterpolatedFix(const BuoyTrack& buoy, double t, double* sigma) {
  const auto& f = buoy.fixes();
  auto after = std::lower_bound(f.begin(), f.end(), t, [](const BuoyFix& x, double time) { return x.time_s < time; });
  if (after == f.end()) after = std::prev(f.end());
  if (after == f.begin() || after->time_s == t) {
    *sigma = after->sigma_m;
    return after->position_en_m;
  }
  const BuoyFix& a = *std::prev(after);
  const double w = (t - a.time_s) / (after->time_s - a.time_s);
  *sigma = std::sqrt(std::pow((1 - w) * a.sigma_m, 2) + std::pow(w * after->sigma_m, 2));
  return (1 - w) * a.position_en_m + w * after->position_en_m;
}

}  // namespace

SubmapContext::SubmapContext(const SlamPath& p, const BuoyTrack& b, const DepthProfile& depth, const GeorefOptions& o)
    : path(p), buoy(b), options(o) {
  const size_t n = path.size();
  depth_m.resize(n);
  reach_m.assign(n, 0);
  static_reason.assign(n, "");
  dt_s.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const double t = path.time(i);
    depth_m[i] = depth.At(t);
    if (!depth_m[i] || *depth_m[i] < 0) {
      static_reason[i] = "no_depth";
    } else if (*depth_m[i] >= options.tether_length_m) {
      static_reason[i] = "too_deep";
    } else {
      reach_m[i] = TetherReach(options.tether_length_m, *depth_m[i]);
      if (!buoy.Bracketed(t, options.max_fix_gap_s)) static_reason[i] = "gps_gap";
    }
    const double before = i > 0 ? std::min(t - path.time(i - 1), options.max_fix_gap_s) : 0;
    const double after = i + 1 < n ? std::min(path.time(i + 1) - t, options.max_fix_gap_s) : 0;
    dt_s[i] = (before + after) / 2;
  }
  for (const SlamLeg& leg : path.legs()) leg_speed_mps.push_back(buoy.MedianSpeed(leg.start_s, leg.end_s));
}

TargetSet SelectFromBuoy(const SubmapContext& c) {
  const GeorefOptions& o = c.options;
  TargetSet s = EmptySet(c.path.size());
  for (size_t i = 0; i < c.path.size(); ++i) {
    std::string& reason = s.reason[i];
    reason = c.static_reason[i];
    if (!reason.empty()) continue;
    const int leg = c.path.leg(i);
    if (leg < 0) {
      reason = "turning";
      continue;
    }
    const double t = c.path.time(i);
    const SlamLeg& span = c.path.legs()[leg];
    const BuoyLocalFit fit = c.buoy.FitAt(t, WindowFor(c, i, leg), span.start_s, span.end_s);
    if (!fit.ok) {
      reason = "gps_gap";
      continue;
    }
    const double speed = fit.velocity_en_mps.norm();
    const double taut_time = TautTime(c.reach_m[i], speed);
    const double look_back = std::max(taut_time, 10.0);
    if (c.path.SinceTurn(i) < taut_time)
      reason = "after_turn";
    else if (c.path.Straightness(t - look_back, t) < o.min_straightness)
      reason = "not_straight";
    else if (c.path.SpeedVariation(t - look_back, t) > o.max_speed_variation)
      reason = "unsteady";
    else if (speed < std::max(o.min_buoy_speed_mps, 0.5 * c.leg_speed_mps[leg]))
      reason = "buoy_slow";
    else if (fit.dropped > o.max_dropped_fraction * (fit.fixes + fit.dropped))
      reason = "buoy_inconsistent";
    if (!reason.empty()) continue;
    const Eigen::Vector2d u = fit.velocity_en_mps / speed;
    const Eigen::Vector2d vehicle = VehicleFromBuoy(fit.position_en_m, u, c.reach_m[i]);
    s.target_enu_m[i] = {vehicle.x(), vehicle.y(), -*c.depth_m[i]};
    s.towing[i] = u;
    const double direction_sigma = std::max(fit.direction_sigma_rad, o.min_direction_sigma_deg * kDeg);
    s.gps_sigma_m[i] = c.buoy.SigmaAt(t);
    s.sigma_m[i] = std::sqrt(TargetVariance(c, i, s.gps_sigma_m[i], direction_sigma, 0));
  }
  return s;
}

TargetSet SelectWithModel(const SubmapContext& c, const Similarity& fit, double heading_sigma_rad) {
  const GeorefOptions& o = c.options;
  const SlamPath& path = c.path;
  TargetSet s = EmptySet(path.size());
  s.model = true;
  if (path.size() == 0) return s;

  // The buoy behind the mapped vehicle path, from the fix nearest the start.
  constexpr double kStep = 0.05;  // 3 cm at 0.6 m/s: the tractrix to a millimetre
  const double t0 = std::max(path.time(0), c.buoy.start_s());
  const double t1 = path.time(path.size() - 1);
  const int steps = std::max(1, static_cast<int>(std::ceil((t1 - t0) / kStep)) + 1);
  double sigma0 = 0;
  TowedBuoy towed(InterpolatedFix(c.buoy, t0, &sigma0));
  std::vector<Eigen::Vector2d> buoy_at(steps), vehicle_at(steps);
  std::vector<bool> taut(steps);
  double reach = 0;
  for (size_t i = 0; i < path.size(); ++i) reach = std::max(reach, c.reach_m[i]);
  size_t next = 0;
  for (int k = 0; k < steps; ++k) {
    const double t = t0 + k * kStep;
    while (next + 1 < path.size() && path.time(next) < t) ++next;
    if (c.reach_m[next] > 0) reach = c.reach_m[next];
    vehicle_at[k] = fit.Apply(path.PositionAt(t)).head<2>();
    taut[k] = towed.Step(vehicle_at[k], reach);
    buoy_at[k] = towed.position();
  }
  auto step_of = [&](double t) { return std::clamp(static_cast<int>(std::lround((t - t0) / kStep)), 0, steps - 1); };

  for (size_t i = 0; i < path.size(); ++i) {
    std::string& reason = s.reason[i];
    reason = c.static_reason[i];
    if (!reason.empty()) continue;
    const int leg = path.leg(i);
    if (leg < 0) {
      reason = "turning";
      continue;
    }
    const double t = path.time(i);
    const int k = step_of(t);
    if (t < t0 || !taut[k]) {
      reason = "slack";
      continue;
    }
    // The stretch of taut towing around t within this leg bounds the window.
    int lo = k, hi = k;
    while (lo > 0 && taut[lo - 1]) --lo;
    while (hi + 1 < steps && taut[hi + 1]) ++hi;
    const SlamLeg& span = path.legs()[leg];
    const BuoyLocalFit measured = c.buoy.FitAt(t, WindowFor(c, i, leg), std::max(span.start_s, t0 + lo * kStep),
                                               std::min(span.end_s, t0 + hi * kStep));
    if (!measured.ok) {
      reason = "gps_gap";
      continue;
    }
    const double speed = measured.velocity_en_mps.norm();
    const Eigen::Vector2d offset = vehicle_at[k] - buoy_at[k];
    const Eigen::Vector2d u = offset / std::max(offset.norm(), 1e-9);
    const int a = std::max(k - 20, 0), b = std::min(k + 20, steps - 1);  // +- 1 s
    const double model_speed = b > a ? (buoy_at[b] - buoy_at[a]).norm() / ((b - a) * kStep) : 0;
    const double vehicle_speed = b > a ? (vehicle_at[b] - vehicle_at[a]).norm() / ((b - a) * kStep) : 0;
    const double direction_sigma = std::max(measured.direction_sigma_rad, o.min_direction_sigma_deg * kDeg);
    if (speed < std::max(o.min_buoy_speed_mps, 0.5 * c.leg_speed_mps[leg]))
      reason = "buoy_slow";
    else if (measured.dropped > o.max_dropped_fraction * (measured.fixes + measured.dropped))
      reason = "buoy_inconsistent";
    else if (AngleRad(measured.velocity_en_mps, u) > 3 * direction_sigma)
      reason = "direction_mismatch";
    else if (std::fabs(speed - model_speed) > o.speed_tolerance * vehicle_speed)
      reason = "buoy_speed";
    if (!reason.empty()) continue;
    double gps_sigma = 0;
    const Eigen::Vector2d fix = InterpolatedFix(c.buoy, t, &gps_sigma);
    const Eigen::Vector2d vehicle = VehicleFromBuoy(fix, u, c.reach_m[i]);
    s.target_enu_m[i] = {vehicle.x(), vehicle.y(), -*c.depth_m[i]};
    s.towing[i] = u;
    s.gps_sigma_m[i] = c.buoy.SigmaAt(t);
    s.sigma_m[i] = std::sqrt(TargetVariance(c, i, s.gps_sigma_m[i], heading_sigma_rad, fit.scale));
  }
  return s;
}

}  // namespace seamap
