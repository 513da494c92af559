#include "core/georef/georeferencer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/georef/taut_selection.h"
#include "core/georef/tether.h"
#include "core/georef/tether_fit.h"
#include "core/georef/towed_fit.h"
#include "core/georef/triangle_fit.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kSigmaFloorM = 0.01;

std::string Fixed(double value, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << value;
  return s.str();
}

// A keyframe's record before any fit: when, which line, its depth and why it is not used.
KeyframeGeoref UnfittedKeyframe(const Keyframe& keyframe, const decltype(KeyframeGeoref::depth_m)& depth_m,
                                const std::string& reason) {
  KeyframeGeoref k;
  k.time_s = keyframe.time_s;
  k.line = keyframe.line;
  k.depth_m = depth_m;
  k.reason = reason;
  return k;
}

std::map<std::string, int> CountReasons(const std::vector<std::string>& reasons) {
  std::map<std::string, int> counts;
  for (const auto& r : reasons)
    if (!r.empty()) ++counts[r];
  return counts;
}

std::string ListCounts(const std::map<std::string, int>& counts) {
  std::string out;
  for (const auto& [reason, n] : counts) out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + reason;
  return out.empty() ? "none" : out;
}

struct FitOutcome {
  Similarity fit;
  std::vector<bool> used;
  std::string degenerate;  // the reason, "" when the geometry holds
  double eigen_ratio = 0;
  std::array<int, 3> triangle{-1, -1, -1};
  double triangle_area = 0;
};

class SubmapFitter {
 public:
  SubmapFitter(const SubmapContext& context, double gps_sigma) : c_(context), gps_sigma_(gps_sigma) {}

  FitOutcome Fit(const TargetSet& set) const {
    FitOutcome out;
    const size_t n = c_.path.size();
    std::vector<bool> candidate(n);
    weights_.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      candidate[i] = set.reason[i].empty();
      const double sigma = std::max(set.sigma_m[i], kSigmaFloorM);
      weights_[i] = candidate[i] ? std::max(c_.dt_s[i], 1e-3) / (sigma * sigma) : 0;
    }
    out.used = candidate;
    out.degenerate = Degeneracy(set, out.used, &out.eigen_ratio);
    if (!out.degenerate.empty()) return out;
    if (c_.options.method == GeorefMethod::kTriangle) return FitTriangleOn(set, out);

    // Fit, reject beyond 3 robust sigmas, refit, re-admit those back within bounds.
    for (int round = 0; round < 10; ++round) {
      out.fit = FitOn(set, out.used);
      std::vector<double> residual(n, 0), used_residuals, used_sigmas;
      for (size_t i = 0; i < n; ++i) {
        if (!candidate[i]) continue;
        residual[i] = (set.target_enu_m[i] - out.fit.Apply(c_.path.position(i))).head<2>().norm();
        if (out.used[i]) {
          used_residuals.push_back(residual[i]);
          used_sigmas.push_back(set.sigma_m[i]);
        }
      }
      // The median length of a 2D Gaussian error is 1.1774 sigma; the floor
      // keeps a noise-free survey from rejecting everything.
      const double robust = std::max({Median(used_residuals) / 1.1774, 0.5 * Median(used_sigmas), kSigmaFloorM});
      std::vector<bool> next(n, false);
      for (size_t i = 0; i < n; ++i) next[i] = candidate[i] && residual[i] <= c_.options.outlier_sigmas * robust;
      if (next == out.used) return out;
      double ratio = 0;
      if (!Degeneracy(set, next, &ratio).empty()) break;  // rejecting would leave too little: keep the last set
      out.used = next;
      out.eigen_ratio = ratio;
    }
    out.fit = FitOn(set, out.used);
    return out;
  }

  const std::vector<double>& weights() const { return weights_; }

 private:
  Similarity FitOn(const TargetSet& set, const std::vector<bool>& used) const {
    std::vector<Eigen::Vector3d> from, to, offsets, buoy;
    std::vector<double> w;
    for (size_t i = 0; i < used.size(); ++i) {
      if (!used[i]) continue;
      from.push_back(c_.path.position(i));
      to.push_back(set.target_enu_m[i]);
      w.push_back(weights_[i]);
      const Eigen::Vector3d offset(c_.reach_m[i] * set.towing[i].x(), c_.reach_m[i] * set.towing[i].y(), 0);
      offsets.push_back(offset);
      buoy.push_back(set.target_enu_m[i] - offset);
    }
    const Similarity fixed_targets = FitSimilarity(from, to, w);
    // With the towing directions from the fit's own rotation, fit through
    // the tether: heading weighed at the buoy's lever arms (tether_fit.h).
    return set.model ? FitThroughTether(fixed_targets, from, offsets, buoy, w) : fixed_targets;
  }

  FitOutcome FitTriangleOn(const TargetSet& set, FitOutcome out) const {
    std::vector<int> index;
    std::vector<Eigen::Vector3d> slam;
    for (size_t i = 0; i < out.used.size(); ++i)
      if (out.used[i]) {
        index.push_back(static_cast<int>(i));
        slam.push_back(c_.path.position(i));
      }
    const TriangleChoice choice = LargestTriangle(slam);
    std::array<Eigen::Vector3d, 3> corners, targets;
    for (int k = 0; k < 3; ++k) {
      out.triangle[k] = index[choice.indices[k]];
      corners[k] = c_.path.position(out.triangle[k]);
      targets[k] = set.target_enu_m[out.triangle[k]];
    }
    out.fit = FitTriangle(corners, targets);
    out.triangle_area = choice.area * out.fit.scale * out.fit.scale;
    return out;
  }

  // Why the good keyframes cannot pin a similarity, or "".
  std::string Degeneracy(const TargetSet& set, const std::vector<bool>& used, double* eigen_ratio) const {
    std::vector<Eigen::Vector3d> slam;
    std::vector<double> w;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < used.size(); ++i)
      if (used[i]) {
        slam.push_back(c_.path.position(i));
        w.push_back(weights_[i]);
        centroid += set.target_enu_m[i].head<2>();
      }
    const int good = static_cast<int>(slam.size());
    if (good < c_.options.min_good_keyframes)
      return "too few taut keyframes: " + std::to_string(good) + " of " + std::to_string(used.size()) +
             " are good (at least " + std::to_string(c_.options.min_good_keyframes) +
             " needed); rejected: " + ListCounts(CountReasons(set.reason));
    centroid /= good;
    double spread = 0;
    for (size_t i = 0; i < used.size(); ++i)
      if (used[i]) spread += (set.target_enu_m[i].head<2>() - centroid).squaredNorm();
    spread = std::sqrt(spread / good);
    if (spread < c_.options.spot_sigmas * gps_sigma_)
      return "all fixes in one spot: the good keyframes' targets lie within " + Fixed(spread, 2) +
             " m RMS of their centroid, under " + Fixed(c_.options.spot_sigmas, 0) + " GPS sigmas (" +
             Fixed(gps_sigma_, 2) + " m): scale and rotation cannot be known";
    *eigen_ratio = EigenRatio(slam, w);
    if (*eigen_ratio < c_.options.min_eigen_ratio)
      return "straight line: the good keyframes lie on one line (sqrt(l2/l1) = " + Fixed(*eigen_ratio, 3) + " < " +
             Fixed(c_.options.min_eigen_ratio, 3) +
             "), so the rotation about it cannot be known; survey at least two legs apart";
    return "";
  }

  const SubmapContext& c_;
  double gps_sigma_;
  mutable std::vector<double> weights_;
};

// Fills what the report says about a fit: residuals, bias, the fixes behind
// it and the uncertainties (with every error term, and with GPS alone: the bound).
void Summarise(const SubmapContext& c, const TargetSet& set, const FitOutcome& fit, const std::vector<double>& weights,
               SubmapGeoref* out) {
  const size_t n = c.path.size();
  std::vector<Eigen::Vector3d> slam;
  std::vector<double> full_h, gps_h, vertical;
  double sq = 0, bias = 0, bias_w = 0;
  const double rate = c.buoy.fix_rate_hz();
  const double slam_sigma = fit.fit.scale * c.path.NoiseSigma();
  const double vertical_var = std::pow(c.options.depth_sigma_m, 2) + slam_sigma * slam_sigma;
  out->good_duration_s = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!fit.used[i]) continue;
    const Eigen::Vector2d r = (set.target_enu_m[i] - fit.fit.Apply(c.path.position(i))).head<2>();
    sq += r.squaredNorm();
    bias += weights[i] * r.dot(set.towing[i]);
    bias_w += weights[i];
    out->good_duration_s += c.dt_s[i];
    const double fixes = rate * c.dt_s[i];  // information counts fixes, not keyframes
    slam.push_back(c.path.position(i));
    full_h.push_back(fixes / std::pow(std::max(set.sigma_m[i], kSigmaFloorM), 2));
    gps_h.push_back(fixes / std::pow(std::max(set.gps_sigma_m[i], kSigmaFloorM), 2));
    vertical.push_back(fixes / vertical_var);
  }
  out->good = static_cast<int>(slam.size());
  out->rmse_m = out->good ? std::sqrt(sq / out->good) : 0;
  out->along_track_bias_m = bias_w > 0 ? bias / bias_w : 0;
  out->n_eff = rate * out->good_duration_s;
  out->uncertainty = PredictUncertainty(fit.fit, slam, full_h, vertical);
  const FitUncertainty bound = PredictUncertainty(fit.fit, slam, gps_h, vertical);
  double predicted = 0;
  for (size_t i = 0; i < n; ++i) predicted += std::pow(bound.HorizontalSigma(fit.fit, c.path.position(i)), 2);
  out->predicted_rmse_m = n ? std::sqrt(predicted / n) : 0;
  out->gps_bound_rmse_m = out->predicted_rmse_m;
}

// The forward axis: image-up for a camera looking down (the default mount),
// else the optical axis; each keyframe's heading along it.
void SetHeadings(const std::string& source, SubmapGeoref* out) {
  int vertical = 0, looking_up = 0;
  for (const auto& k : out->keyframes) {
    const double z = k.enu_from_cam(2, 2);
    if (std::fabs(z) >= std::cos(45 * kDeg)) ++vertical;
    if (z >= std::cos(45 * kDeg)) ++looking_up;
  }
  const bool image_up = 2 * vertical >= static_cast<int>(out->keyframes.size());
  out->forward_axis = image_up ? "image_up" : "optical_axis";
  if (image_up && 2 * looking_up > vertical)
    out->warnings.push_back(source +
                            ": the mapped camera looks up, not down: mirrored or mis-ordered input "
                            "(world-to-camera poses, or the quaternion's scalar first)?");
  for (auto& k : out->keyframes) k.heading_deg = CameraHeadingDeg(k.enu_from_cam, image_up);
}

// --method tether: the similarity, the reach and the buoy's way of following
// fitted jointly to every fix (towed_fit.h), started from the buoy in the
// vehicle's wake; the keyframes the model tows on a taut tether are the good
// ones, and they must pin the similarity.
void FitTether(const SubmapContext& c, const std::vector<Keyframe>& keyframes, SubmapGeoref* out) {
  const size_t n = c.path.size();
  std::vector<double> depth(n, NAN);
  for (size_t i = 0; i < n; ++i)
    if (c.depth_m[i]) depth[i] = *c.depth_m[i];
  const double speed = c.buoy.MedianSpeed(c.path.time(0), c.path.time(n - 1));
  const Similarity start = WakeStart(c.path, c.reach_m, depth, c.buoy, speed);
  TowedFitOptions to;
  to.depth_sigma_m = c.options.depth_sigma_m;
  to.min_taut_fixes = c.options.min_good_keyframes;
  to.clock_sigma_s = c.options.clock_sigma_s;
  to.sag_sigma = c.options.sag_sigma;
  const TowedFitResult r = FitTowedBuoy(c.path, c.reach_m, depth, c.buoy, start, c.path.NoiseSigma(), to);

  std::vector<std::string> reasons(n);
  std::vector<Eigen::Vector3d> slam;
  std::vector<double> w;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    reasons[i] = c.static_reason[i];
    if (reasons[i].empty() && !(r.ok && r.keyframe_taut[i])) reasons[i] = r.ok ? "slack" : "no_fit";
    if (!reasons[i].empty()) continue;
    slam.push_back(c.path.position(i));
    w.push_back(c.dt_s[i]);
    centroid += r.fit.Apply(c.path.position(i)).head<2>();
  }
  const std::map<std::string, int> counts = CountReasons(reasons);
  out->rejected = counts;
  out->good = static_cast<int>(slam.size());
  auto refuse = [&](const std::string& why) {
    out->degenerate = true;
    out->reason = why;
    out->keyframes.clear();
    for (size_t i = 0; i < n; ++i) out->keyframes.push_back(UnfittedKeyframe(keyframes[i], c.depth_m[i], reasons[i]));
  };
  if (!r.ok || out->good < c.options.min_good_keyframes)
    return refuse("too few taut keyframes: " + std::to_string(out->good) + " of " + std::to_string(n) +
                  " are good (at least " + std::to_string(c.options.min_good_keyframes) + " needed; " +
                  std::to_string(r.taut_fixes) + " fixes on a taut tether); rejected: " + ListCounts(counts));
  centroid /= out->good;
  double spread = 0;
  for (size_t i = 0; i < n; ++i)
    if (reasons[i].empty()) spread += (r.fit.Apply(c.path.position(i)).head<2>() - centroid).squaredNorm();
  spread = std::sqrt(spread / out->good);
  if (spread < c.options.spot_sigmas * out->gps_sigma_m)
    return refuse("all fixes in one spot: the good keyframes lie within " + Fixed(spread, 2) +
                  " m RMS of their centroid, under " + Fixed(c.options.spot_sigmas, 0) + " GPS sigmas (" +
                  Fixed(out->gps_sigma_m, 2) + " m): scale and rotation cannot be known");
  out->eigen_ratio = EigenRatio(slam, w);
  if (out->eigen_ratio < c.options.min_eigen_ratio)
    return refuse("straight line: the good keyframes lie on one line (sqrt(l2/l1) = " + Fixed(out->eigen_ratio, 3) +
                  " < " + Fixed(c.options.min_eigen_ratio, 3) +
                  "), so the rotation about it cannot be known; survey at least two legs apart");

  out->fitted = true;
  out->transform = r.fit;
  out->rounds = r.iterations;
  out->outliers = r.outliers;
  out->rmse_m = r.residual_rms_m;
  out->predicted_rmse_m = r.predicted_rmse_m;
  out->gps_bound_rmse_m = r.gps_bound_rmse_m;
  out->model_bound_rmse_m = r.model_bound_rmse_m;
  out->along_track_bias_m = r.along_cross_bias_m.x();
  out->reach_factor = r.reach_factor;
  out->reach_factor_sigma = r.reach_factor_sigma;
  out->reach_estimated = r.reach_estimated;
  out->wake_estimated = r.wake_estimated;
  out->current_estimated = r.current_estimated;
  out->lag_estimated = r.lag_estimated;
  out->lag_s = r.lag_s;
  out->lag_sigma_s = r.lag_sigma_s;
  {
    const Eigen::Matrix2d& cov = r.free_reach_lag_covariance;
    out->along_track_offset_m = r.along_track_offset_m;
    out->along_track_offset_sigma_m = r.along_track_offset_sigma_m;
    const double scale = std::sqrt(std::max(cov(0, 0) * cov(1, 1), 1e-300));
    out->reach_lag_correlation = cov(0, 1) / scale;
    out->reach_lag_separable = std::fabs(out->reach_lag_correlation) < 0.9;
    out->unseen_offset_rmse_m = r.unseen_offset_rmse_m;
    out->selection_spread_rmse_m = r.selection_spread_rmse_m;
    if (r.along_track_offset_unseen)
      out->warnings.push_back(
          out->source + ": the buoy's distance behind the vehicle (tether reach, fixes' lag) is seen only to +-" +
          Fixed(out->along_track_offset_sigma_m, 2) +
          " m on this geometry (legs all flown one way, or a spiral): a sagging tether or a clock offset "
          "would move the map along the track by up to that. predicted_rmse_m includes what a clock offset of "
          "+-" +
          Fixed(c.options.clock_sigma_s, 2) + " s or a sag of " + Fixed(100 * c.options.sag_sigma, 1) +
          " % may do (--clock-sigma, --sag-sigma: set them to what is known); legs flown both ways would see it");
  }
  out->current_mps = r.current_mps;
  out->current_sigma_mps = r.current_covariance.diagonal().cwiseMax(0).cwiseSqrt();
  out->wake_share = r.wake_share;
  out->wake_share_sigma = r.wake_share_sigma;
  out->variance_factor = r.variance_factor;
  out->correlation_factor = r.correlation_factor;
  out->taut_model_sigma_m = r.taut_model_sigma_m;
  out->slack_model_sigma_m = r.slack_model_sigma_m;
  out->fixes_used = r.fixes - r.outliers;
  out->taut_fixes = r.taut_fixes;
  out->good_duration_s = 0;
  for (size_t i = 0; i < n; ++i)
    if (reasons[i].empty()) out->good_duration_s += c.dt_s[i];
  out->n_eff = r.taut_fixes;
  out->keyframes.clear();
  for (size_t i = 0; i < n; ++i) {
    KeyframeGeoref k = UnfittedKeyframe(keyframes[i], c.depth_m[i], reasons[i]);
    k.good = reasons[i].empty();
    k.position_enu_m = r.fit.Apply(keyframes[i].position_slam);
    k.enu_from_cam = r.fit.rotation * keyframes[i].world_from_cam.toRotationMatrix();
    k.sigma_m = r.keyframe_sigma_m[i];
    out->keyframes.push_back(k);
  }
}

}  // namespace

double CameraHeadingDeg(const Eigen::Matrix3d& enu_from_cam, bool image_up) {
  const Eigen::Vector3d forward =
      image_up ? Eigen::Vector3d(-enu_from_cam.col(1)) : Eigen::Vector3d(enu_from_cam.col(2));
  double heading = std::atan2(forward.x(), forward.y()) / kDeg;
  if (heading < 0) heading += 360;
  return heading >= 360 ? 0 : heading;
}

SubmapGeoref GeoreferenceSubmap(const std::string& source, const std::vector<Keyframe>& keyframes,
                                const BuoyTrack& buoy, const DepthProfile& depth, const GeorefOptions& options) {
  SubmapGeoref out;
  out.source = source;
  out.method = options.method == GeorefMethod::kTriangle ? "triangle"
               : options.method == GeorefMethod::kTether ? "tether"
                                                         : "umeyama";
  const bool overlap = std::any_of(keyframes.begin(), keyframes.end(), [&](const Keyframe& k) {
    return k.time_s >= buoy.start_s() && k.time_s <= buoy.end_s();
  });
  if (!overlap)
    throw InputError(source, keyframes.front().line, "timestamp",
                     "no keyframe falls within the buoy's time span: keyframes " + Fixed(keyframes.front().time_s, 3) +
                         " .. " + Fixed(keyframes.back().time_s, 3) + " s, buoy fixes " + Fixed(buoy.start_s(), 3) +
                         " .. " + Fixed(buoy.end_s(), 3) +
                         " s; both must use the same clock (an epoch or time-zone mix-up?)");

  const SlamPath path(keyframes, options.path);
  out.resets = path.SuspectedResets();
  const SubmapContext context(path, buoy, depth, options);
  out.gps_sigma_m = buoy.sigma_m();
  out.gps_sigma_source = buoy.sigma_source();
  out.fix_rate_hz = buoy.fix_rate_hz();
  std::vector<double> reaches;
  for (double r : context.reach_m)
    if (r > 0) reaches.push_back(r);
  out.reach_m = Median(reaches);
  const double t_first = keyframes.front().time_s, t_last = keyframes.back().time_s;
  out.taut_time_s = TautTime(out.reach_m, buoy.MedianSpeed(t_first, t_last));

  auto fill_keyframes = [&](const TargetSet* set, const FitOutcome* fit) {
    out.keyframes.clear();
    for (size_t i = 0; i < keyframes.size(); ++i) {
      KeyframeGeoref k = UnfittedKeyframe(keyframes[i], context.depth_m[i], set ? set->reason[i] : std::string());
      if (set) {
        k.has_target = set->reason[i].empty();
        k.target_enu_m = set->target_enu_m[i];
      }
      if (fit) {
        k.good = fit->used[i];
        if (k.has_target && !k.good) k.reason = "outlier";
        k.position_enu_m = fit->fit.Apply(keyframes[i].position_slam);
        k.enu_from_cam = fit->fit.rotation * keyframes[i].world_from_cam.toRotationMatrix();
      }
      out.keyframes.push_back(k);
    }
    std::vector<std::string> reasons;
    for (const auto& k : out.keyframes) reasons.push_back(k.reason);
    out.rejected = CountReasons(reasons);
  };

  // A hovering vehicle (or a moored buoy): nothing to fit a rotation or a scale to.
  const double spread = buoy.Spread(t_first, t_last);
  if (spread < options.spot_sigmas * out.gps_sigma_m) {
    out.degenerate = true;
    out.reason = "all fixes in one spot: the buoy's fixes during the sub-map lie within " + Fixed(spread, 2) +
                 " m RMS of their centroid, under " + Fixed(options.spot_sigmas, 0) + " GPS sigmas (" +
                 Fixed(out.gps_sigma_m, 2) + " m): scale and rotation cannot be known";
    fill_keyframes(nullptr, nullptr);
    return out;
  }

  if (options.method == GeorefMethod::kTether) {
    FitTether(context, keyframes, &out);
    if (!out.fitted) return out;
    SetHeadings(source, &out);
    return out;
  }

  const SubmapFitter fitter(context, out.gps_sigma_m);
  TargetSet set = SelectFromBuoy(context);
  FitOutcome fit = fitter.Fit(set);
  std::vector<double> weights = fitter.weights();
  out.rounds = 1;
  if (!fit.degenerate.empty()) {
    out.degenerate = true;
    out.reason = fit.degenerate;
    fill_keyframes(&set, nullptr);
    return out;
  }
  // Targets from the tether model behind the fitted path, until the good set holds.
  for (int round = 2; options.method == GeorefMethod::kUmeyama && round <= options.max_rounds; ++round) {
    Summarise(context, set, fit, weights, &out);
    const double heading_sigma = out.uncertainty.ok ? out.uncertainty.rotation_sigma_deg.z() * kDeg : 0.01;
    TargetSet next = SelectWithModel(context, fit.fit, heading_sigma);
    FitOutcome again = fitter.Fit(next);
    if (!again.degenerate.empty()) {
      out.warnings.push_back("round " + std::to_string(round) + " with the tether model found " + again.degenerate +
                             "; kept round " + std::to_string(round - 1) + "'s fit");
      break;
    }
    const bool same = again.used == fit.used;
    set = std::move(next);
    fit = std::move(again);
    weights = fitter.weights();
    out.rounds = round;
    if (same) break;
  }

  Summarise(context, set, fit, weights, &out);
  out.fitted = true;
  out.transform = fit.fit;
  out.eigen_ratio = fit.eigen_ratio;
  out.triangle = fit.triangle;
  out.triangle_area_m2 = fit.triangle_area;
  fill_keyframes(&set, &fit);
  out.outliers = out.rejected.count("outlier") ? out.rejected.at("outlier") : 0;

  SetHeadings(source, &out);
  return out;
}

}  // namespace seamap
