#include "core/georef/towed_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "core/georef/held_offset.h"
#include "core/georef/towed_fit_comparison.h"
#include "core/georef/towed_fit_problem.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

using towed_fit::Filled;
using towed_fit::kParams;
using towed_fit::Model;
using towed_fit::ParamMatrix;
using towed_fit::Params;
using towed_fit::PriorInformation;
using towed_fit::PriorOffset;
using towed_fit::Problem;
using towed_fit::Simulation;
using towed_fit::TimeSeries;

// chi-square with 2 degrees of freedom at the 2-sigma level (95.45 %)
constexpr double kCurrentShows = 6.18;
// A current held at its default for want of significance is taken, in the
// error estimate, as about half its standard error (a quarter of its
// variance): held, a 0.006 m/s current across a transect (1.3 standard
// errors) put the map 0.36 m off where 0.19 m was predicted. Measured on the
// stress set (docs/GEOREF.md, "fifth pass"): a quarter to 0.3 brings that
// survey inside 0.67-1.5 and none below it; 0.35 puts one below.
constexpr double kHeldCurrentShare = 0.25;

// One way to split the buoy's shift along the track between the reach and
// the lag (reach only, lag only, both) and its fit.
struct ReachLagCandidate {
  bool reach = false, lag = false, current = false;
  TowedFitOptions options;
  Params theta = Params::Zero();
  TowedFitResult fit;
  double bic = 0;  // robust cost (chi-square units) + free parameters x ln(observations)
};

}  // namespace

TowedFitResult FitTowedBuoy(const SlamPath& path, const std::vector<double>& reach_m,
                            const std::vector<double>& depth_m, const BuoyTrack& buoy, const Similarity& start,
                            double slam_sigma, const TowedFitOptions& options) {
  if (path.size() < 3) return {};
  const Problem problem(path, reach_m, depth_m, buoy, start, slam_sigma, options);
  const size_t nf = problem.fixes();
  if (nf < 3) return {};
  const auto& fixes = problem.fix_list();

  Eigen::VectorXd w;  // per residual
  std::vector<bool> kept(nf, true);
  std::vector<double> sigma(nf, 0);
  double taut_model = 0, slack_model = 0;
  int iterations = 0;
  Simulation sim;
  // Levenberg-Marquardt with reweighting; o: the priors to use.
  auto solve = [&](Params theta, const TowedFitOptions& o) {
    double lambda = 1e-3;
    for (int iteration = 0; iteration < o.max_iterations; ++iteration) {
      iterations = iteration + 1;
      const Eigen::VectorXd r = problem.Residuals(theta, &sim);
      const Model m = problem.ModelAt(theta);
      // The model's own noise per class, from the fixes' scatter beyond the GPS's.
      std::vector<double> length[2], gps_var;
      for (size_t j = 0; j < nf; ++j) {
        const int c = sim.taut[j] && sim.settled[j] ? 0 : 1;
        length[c].push_back(r.segment<2>(2 * j).norm());
        gps_var.push_back(fixes[j].sigma * fixes[j].sigma);
      }
      const double gps = Median(gps_var);
      auto model_sigma = [&](std::vector<double>& l) {
        if (l.size() < 5) return 0.0;
        const double ms = std::pow(Median(l) / 1.1774, 2);
        return std::sqrt(std::max(ms - gps, 0.0));
      };
      taut_model = model_sigma(length[0]);
      slack_model = std::max(model_sigma(length[1]), taut_model);
      w.setZero(r.size());
      for (size_t j = 0; j < nf; ++j) {
        const double extra = sim.taut[j] && sim.settled[j] ? taut_model : slack_model;
        sigma[j] = std::hypot(std::hypot(fixes[j].sigma, extra), sim.start_sigma_m[j]);
        const double z = r.segment<2>(2 * j).norm() / sigma[j];
        kept[j] = iteration < 2 || z <= o.outlier_sigmas;
        const double huber = z <= o.huber_k ? 1.0 : o.huber_k / z;
        w(2 * j) = w(2 * j + 1) = kept[j] ? huber / (sigma[j] * sigma[j]) : 0;
      }
      const double depth_w = 1 / std::pow(problem.DepthSigma(m), 2);
      for (Eigen::Index k = 2 * nf; k < r.size(); ++k) w(k) = depth_w;

      const Eigen::MatrixXd j = problem.Jacobian(theta);
      const ParamMatrix prior = PriorInformation(o);
      const ParamMatrix h = j.transpose() * w.asDiagonal() * j + prior;
      // r = data - model and j = d r / d theta: the gradient of (r^T W r) / 2 is j^T W r.
      const Params g = j.transpose() * (w.asDiagonal() * r) + prior * PriorOffset(theta, o);
      const double cost = r.dot(w.asDiagonal() * r) + PriorOffset(theta, o).dot(prior * PriorOffset(theta, o));
      bool improved = false;
      Params delta = Params::Zero();
      for (int attempt = 0; attempt < 10; ++attempt) {
        ParamMatrix damped = h;
        damped.diagonal() += lambda * h.diagonal();
        Params next = theta - damped.ldlt().solve(g);
        next(8) = std::clamp(next(8), 0.0, 1.0);
        const Eigen::VectorXd rn = problem.Residuals(next);
        const double next_cost = rn.dot(w.asDiagonal() * rn) + PriorOffset(next, o).dot(prior * PriorOffset(next, o));
        if (next_cost <= cost) {
          delta = next - theta;
          theta = next;
          lambda = std::max(lambda / 10, 1e-7);
          improved = true;
          break;
        }
        lambda *= 10;
      }
      const bool small = delta.head<3>().norm() < 1e-7 && std::fabs(delta(3)) < 1e-7 &&
                         delta.segment<3>(4).norm() < 1e-4 && std::fabs(delta(7)) < 1e-5 && std::fabs(delta(8)) < 1e-4;
      if ((!improved || small) && iteration >= 3) break;
    }
    return theta;
  };

  auto finish = [&](const Params& theta, const TowedFitOptions& o) {
    TowedFitResult res;
    res.iterations = iterations;
    // The final state: residuals, weights (no Huber: the covariance of a converged M-estimate near Gaussian).
    const Eigen::VectorXd r = problem.Residuals(theta, &sim);
    const Model m = problem.ModelAt(theta);
    const Eigen::MatrixXd j = problem.Jacobian(theta);
    Eigen::VectorXd wf = Eigen::VectorXd::Zero(r.size());
    Eigen::VectorXd wg = Eigen::VectorXd::Zero(r.size());  // GPS alone, taut fixes
    Eigen::VectorXd wm = Eigen::VectorXd::Zero(r.size());  // GPS alone, every fix kept
    double chi2 = 0, taut_sq = 0;
    int taut_n = 0;
    Eigen::Vector2d bias = Eigen::Vector2d::Zero();
    std::vector<std::pair<double, Eigen::Vector2d>> normalised;  // time, residual / sigma (taut fixes)
    res.outliers = 0;
    for (size_t k = 0; k < nf; ++k) {
      const bool taut = sim.taut[k] && sim.settled[k];
      sigma[k] = std::hypot(std::hypot(fixes[k].sigma, taut ? taut_model : slack_model), sim.start_sigma_m[k]);
      const Eigen::Vector2d rk = r.segment<2>(2 * k);
      {  // Huber's cost (twice, so that it reads as chi-square) against the GPS noise alone, outliers capped
        const double z = std::min(rk.norm() / fixes[k].sigma, o.outlier_sigmas);
        res.robust_cost += z <= o.huber_k ? z * z : 2 * o.huber_k * z - o.huber_k * o.huber_k;
        res.cost_observations += 2;
      }
      if (rk.norm() > o.outlier_sigmas * sigma[k]) {
        ++res.outliers;
        continue;
      }
      wf(2 * k) = wf(2 * k + 1) = 1 / (sigma[k] * sigma[k]);
      wm(2 * k) = wm(2 * k + 1) = 1 / (fixes[k].sigma * fixes[k].sigma);
      if (!taut) continue;
      wg(2 * k) = wg(2 * k + 1) = 1 / (fixes[k].sigma * fixes[k].sigma);
      chi2 += rk.squaredNorm() / (sigma[k] * sigma[k]);
      taut_sq += rk.squaredNorm();
      ++taut_n;
      const Eigen::Vector2d u = sim.towing[k];
      bias += Eigen::Vector2d(rk.dot(u), u.x() * rk.y() - u.y() * rk.x());
      normalised.push_back({fixes[k].time_s, rk / sigma[k]});
    }
    const double depth_w = 1 / std::pow(problem.DepthSigma(m), 2);
    for (Eigen::Index k = 2 * nf; k < r.size(); ++k) wf(k) = wg(k) = wm(k) = depth_w;
    res.fixes = static_cast<int>(nf);
    res.taut_fixes = taut_n;
    if (taut_n < o.min_taut_fixes) return res;
    res.residual_rms_m = std::sqrt(taut_sq / taut_n);
    res.along_cross_bias_m = bias / taut_n;
    res.variance_factor = std::max(1.0, chi2 / std::max(2.0 * taut_n - kParams, 1.0));
    res.taut_model_sigma_m = taut_model;
    res.slack_model_sigma_m = slack_model;

    // Correlation in time: the variance of batch means over what white noise would give.
    {
      double sum_batch = 0, sum_all = 0;
      int batches = 0;
      size_t a = 0;
      while (a < normalised.size()) {
        size_t b = a;
        Eigen::Vector2d mean = Eigen::Vector2d::Zero();
        while (b < normalised.size() && normalised[b].first < normalised[a].first + o.batch_s)
          mean += normalised[b++].second;
        const double n = static_cast<double>(b - a);
        if (n >= 3) {
          mean /= n;
          sum_batch += n * mean.squaredNorm() / 2;
          ++batches;
        }
        a = b;
      }
      for (const auto& e : normalised) sum_all += e.second.squaredNorm() / 2;
      if (batches >= 4 && sum_all > 0)
        res.correlation_factor = std::max(1.0, (sum_batch / batches) / (sum_all / normalised.size()));
    }

    const ParamMatrix h = j.transpose() * wf.asDiagonal() * j + PriorInformation(o);
    const ParamMatrix covariance = h.inverse() * res.variance_factor * res.correlation_factor;
    Eigen::Matrix<double, 7, 7> hg = (j.leftCols<7>().transpose() * wg.asDiagonal() * j.leftCols<7>()).eval();
    Eigen::FullPivLU<Eigen::Matrix<double, 7, 7>> lu(hg);
    const bool bound_ok = lu.isInvertible();
    const Eigen::Matrix<double, 7, 7> bound_cov =
        bound_ok ? Eigen::Matrix<double, 7, 7>(lu.inverse()) : Eigen::Matrix<double, 7, 7>::Zero();
    if (!covariance.allFinite()) return res;
    // The bound with the buoy parameters this fit estimates unknown too (a current, a sag, a lag): GPS noise
    // alone on every fix, the depths, the priors; what no estimator of this model can beat.
    const ParamMatrix model_bound_cov = (j.transpose() * wm.asDiagonal() * j + PriorInformation(o)).inverse();

    // How this fit's map would move were the reach or the lag different,
    // the parameters it estimates following: -H_rr^-1 H_r,(k, lag) from its
    // information (the held parameters stay held by their priors).
    Eigen::Matrix<double, kParams, 2> per_reach_lag = Eigen::Matrix<double, kParams, 2>::Zero();
    {
      ParamMatrix rest = h;
      Eigen::Matrix<double, kParams, 2> coupling;
      coupling << h.col(7), h.col(11);
      for (int k : {7, 11}) {
        rest.row(k).setZero();
        rest.col(k).setZero();
        rest(k, k) = 1;
        coupling.row(k).setZero();
      }
      per_reach_lag = -rest.ldlt().solve(coupling);
    }

    const double slam_m = m.fit.scale * slam_sigma;
    double sq = 0, bound_sq = 0, model_bound_sq = 0;
    for (size_t i = 0; i < path.size(); ++i) {
      const Eigen::Matrix<double, 2, kParams> ji = problem.KeyframeJacobian(m, path.position(i));
      const double var = (ji * covariance * ji.transpose()).trace() + 2 * slam_m * slam_m;
      res.keyframe_sigma_m.push_back(std::sqrt(std::max(var, 0.0)));
      res.shift_per_reach_lag.push_back(ji * per_reach_lag);
      sq += var;
      const Eigen::Matrix<double, 2, 7> jb = ji.leftCols<7>();
      bound_sq += (jb * bound_cov * jb.transpose()).trace();
      model_bound_sq += (ji * model_bound_cov * ji.transpose()).trace();
    }
    res.model_bound_rmse_m = std::sqrt(std::max(model_bound_sq, 0.0) / path.size());
    res.predicted_rmse_m = std::sqrt(sq / path.size());
    res.gps_bound_rmse_m = std::sqrt(std::max(bound_sq, 0.0) / path.size());
    res.fit = m.fit;
    res.reach_factor = m.reach_factor;
    res.reach_factor_sigma = std::sqrt(std::max(covariance(7, 7), 0.0)) * m.reach_factor;
    res.wake_share = m.wake_share;
    res.wake_share_sigma = std::sqrt(std::max(covariance(8, 8), 0.0));
    res.current_mps = m.current_mps;
    res.current_covariance = covariance.block<2, 2>(9, 9);
    res.lag_s = m.lag_s;
    res.lag_sigma_s = std::sqrt(std::max(covariance(11, 11), 0.0));
    res.reach_lag_covariance << covariance(7, 7), covariance(7, 11), covariance(11, 7), covariance(11, 11);
    res.keyframe_taut = sim.keyframe_taut;
    res.ok = true;
    return res;
  };

  // First everything free (loose priors). Then the reach is the straight
  // tether's unless the data put it away from it, and the buoy a pure
  // tractrix or a pure wake follower unless the data want a mix: a free
  // parameter the data barely see costs accuracy (on a spiral both trade
  // with the heading and the scale).
  TowedFitOptions loose = options, fixed = options;
  loose.reach_prior_sigma = std::max(options.reach_prior_sigma, 0.15);
  const Params free_theta = solve(problem.Initial(), loose);
  TowedFitResult out = finish(free_theta, loose);
  if (!out.ok) return out;
  out.free_reach_factor = out.reach_factor;
  out.free_lag_s = out.lag_s;
  out.free_reach_lag_covariance = out.reach_lag_covariance;
  Params again = free_theta;
  bool refit = false;
  // The reach and the lag both move the buoy along the track, so they are
  // tested together: both kept at their defaults unless jointly significant
  // (chi-square, 2 degrees of freedom, beyond 3 sigmas' 99.73 %); both kept
  // when each is significant on its own. Otherwise, where the two trade
  // with each other, the one to keep is chosen by the fits' cost
  // (ReachLagCandidate, BIC), not by significance: the more significant one could
  // take the other's shift and misfit the turns (a clock offset taken as a
  // shorter reach on a transect put the map 0.75 m off where 0.22 m was
  // predicted).
  const Eigen::Matrix2d& cov = out.reach_lag_covariance;
  const Eigen::Vector2d reach_lag(std::log(out.reach_factor), out.lag_s);
  const double z_reach = std::fabs(reach_lag(0)) / std::sqrt(std::max(cov(0, 0), 1e-30));
  const double z_lag = std::fabs(reach_lag(1)) / std::sqrt(std::max(cov(1, 1), 1e-30));
  const bool joint = reach_lag.dot(cov.inverse() * reach_lag) > 11.83;
  bool keep_reach = joint && z_reach > options.reach_significance;
  bool keep_lag = joint && z_lag > options.reach_significance;
  const bool choose_reach_lag = joint && !(keep_reach && keep_lag);
  for (double pure : {0.0, 1.0})
    if (std::fabs(out.wake_share - pure) <= options.reach_significance * out.wake_share_sigma) {
      fixed.wake_prior_mean = pure;
      fixed.wake_prior_sigma = 1e-5;
      again(8) = pure;
      refit = true;
      break;
    }
  // The current: zero unless it shows (chi-square with 2 degrees of freedom beyond 3 sigmas' 99.73 %).
  bool current_held = false;
  if (out.current_mps.dot(out.current_covariance.inverse() * out.current_mps) <= 11.83) {
    fixed.current_prior_mps = 1e-6;
    again.segment<2>(9).setZero();
    refit = true;
    current_held = true;
  }
  auto hold_reach = [](TowedFitOptions& o, Params& theta) {
    o.reach_prior_sigma = 1e-5;
    theta(7) = 0;
  };
  auto hold_lag = [](TowedFitOptions& o, Params& theta) {
    o.lag_prior_s = 1e-6;
    theta(11) = 0;
  };
  if (!choose_reach_lag) {
    if (!keep_reach) hold_reach(fixed, again);
    if (!keep_lag) hold_lag(fixed, again);
    refit = refit || !keep_reach || !keep_lag;
  }
  if (!refit && !choose_reach_lag) {
    out.reach_estimated = out.wake_estimated = out.current_estimated = out.lag_estimated = true;
    return out;
  }
  auto held_fit = [&](const TowedFitOptions& o, const Params& theta) {
    TowedFitResult r = finish(solve(theta, o), o);
    r.reach_estimated = o.reach_prior_sigma > 1e-3;
    r.wake_estimated = o.wake_prior_sigma > 1e-3;
    r.current_estimated = o.current_prior_mps > 1e-3;
    r.lag_estimated = o.lag_prior_s > 1e-3;
    r.free_reach_factor = out.free_reach_factor;
    r.free_lag_s = out.free_lag_s;
    r.free_reach_lag_covariance = out.free_reach_lag_covariance;
    return r;
  };
  // Reach only, lag only, both: each fitted, the one with the lowest BIC
  // kept; the others' maps, weighted by their BIC, widen the error estimate.
  std::vector<ReachLagCandidate> candidates;
  bool keep_current = !current_held;
  if (choose_reach_lag) {
    // A current held for want of significance in the fit with everything
    // free may show once the shift along the track is split: each split
    // is also tried with the current estimated.
    const int current_choices = current_held ? 2 : 1;
    for (int which = 0; which < 3 * current_choices; ++which) {
      ReachLagCandidate c;
      c.options = fixed;
      c.theta = again;
      c.reach = which % 3 != 1;
      c.lag = which % 3 != 0;
      c.current = !current_held || which >= 3;
      if (!c.reach) hold_reach(c.options, c.theta);
      if (!c.lag) hold_lag(c.options, c.theta);
      if (c.current && current_held) {
        c.options.current_prior_mps = loose.current_prior_mps;
        c.theta.segment<2>(9) = free_theta.segment<2>(9);
      }
      c.fit = held_fit(c.options, c.theta);
      if (!c.fit.ok) continue;
      c.bic = c.fit.robust_cost / std::max(out.variance_factor * out.correlation_factor, 1.0) +
              (c.reach + c.lag + 2 * c.current) * std::log(std::max(c.fit.cost_observations, 2));
      candidates.push_back(std::move(c));
    }
    if (candidates.empty()) return out;
    const auto chosen = std::min_element(candidates.begin(), candidates.end(),
                                         [](const auto& x, const auto& y) { return x.bic < y.bic; });
    fixed = chosen->options;
    again = chosen->theta;
    keep_reach = chosen->reach;
    keep_lag = chosen->lag;
    keep_current = chosen->current;
  }
  TowedFitResult best;
  if (choose_reach_lag) {
    for (const ReachLagCandidate& c : candidates)
      if (c.reach == keep_reach && c.lag == keep_lag && c.current == keep_current) best = c.fit;
  } else {
    best = held_fit(fixed, again);
  }
  if (!best.ok) return out;
  // A parameter held at its default may still move the map more than its
  // estimate's noise would (MovedBeyondChance): the current, then the reach, each
  // freed again from the free fit's value and kept if the map moved beyond chance.
  auto try_free = [&](bool held, auto&& release) {
    if (!held) return;
    TowedFitOptions o = fixed;
    Params theta = again;
    release(o, theta);
    TowedFitResult variant = held_fit(o, theta);
    if (!variant.ok) return;
    const bool moved = MovedBeyondChance(path, variant, 1, best);
    if (!moved) return;
    best = std::move(variant);
    fixed = o;
    again = theta;
  };
  // A held current is freed again where the map moves beyond chance
  // (MovedBeyondChance) and the current itself lowers the cost by more than
  // its 2-sigma level (chi-square, 2 degrees of freedom: 6.18). The map test
  // assumes the freed model right; a current the data barely see that moves
  // the map far beyond chance is taking up a misfit elsewhere: on a transect
  // with a sag and a clock offset, a current lowering the cost by 4.6 moved
  // the map 0.77 m, three times chance (0.06 m held, 0.76 m freed). A real
  // weak current lowered it by 11.2 (1.2 m held, docs/GEOREF.md "fifth pass").
  // Held, the current still moves the map by what it would be beyond its
  // default: a quarter of what freeing it adds to each keyframe's variance
  // (kHeldCurrentShare) goes into the error estimate.
  std::vector<double> held_current_var;  // per keyframe, m^2
  if (!keep_current) {
    TowedFitOptions o = fixed;
    Params theta = again;
    o.current_prior_mps = loose.current_prior_mps;
    theta.segment<2>(9) = free_theta.segment<2>(9);
    TowedFitResult freed = held_fit(o, theta);
    if (freed.ok) {
      const double scale = std::max(out.variance_factor * out.correlation_factor, 1.0);
      const double cost_drop = (best.robust_cost - freed.robust_cost) / scale;
      const bool moved = MovedBeyondChance(path, freed, 2, best);
      if (moved && cost_drop > kCurrentShows) {
        best = std::move(freed);
        fixed = o;
        again = theta;
      } else {
        for (size_t i = 0; i < freed.keyframe_sigma_m.size() && i < best.keyframe_sigma_m.size(); ++i)
          held_current_var.push_back(
              std::max(std::pow(freed.keyframe_sigma_m[i], 2) - std::pow(best.keyframe_sigma_m[i], 2), 0.0));
      }
    }
  }
  try_free(!keep_reach, [&](TowedFitOptions& o, Params& theta) {
    o.reach_prior_sigma = loose.reach_prior_sigma;
    theta(7) = free_theta(7);
  });
  // The offset along the track, reach and lag together, as the fit with
  // both free sees it. Where it is seen worse than twice the held fit's
  // error (a spiral, legs all flown one way), the fixes alone cannot tell
  // whether reach and lag may stay at their defaults: what the offset may
  // be, under the prior of a clock offset and a sag (held_offset.h), times
  // how the held map moves with it, goes into the estimate. The map stays
  // held at the defaults: held at the offset's posterior mean it was 8 %
  // better over the stress sets but a spiral with none was 0.34 m off
  // instead of 0.14 (docs/GEOREF.md, "eighth pass").
  std::vector<double> unseen_var;  // per keyframe, m^2
  {
    std::vector<double> reaches;
    for (double x : reach_m)
      if (x > 0) reaches.push_back(x);
    const double c_t = Median(reaches);
    const double speed = buoy.MedianSpeed(path.time(0), path.time(path.size() - 1));
    const Eigen::Vector2d along(c_t * out.free_reach_factor, speed);  // d offset / d (log k, lag)
    const Eigen::Matrix2d& free_cov = out.free_reach_lag_covariance;
    const double offset_var = along.dot(free_cov * along);
    best.along_track_offset_m = c_t * (out.free_reach_factor - 1) + speed * out.free_lag_s;
    best.along_track_offset_sigma_m = std::sqrt(std::max(offset_var, 0.0));
    best.along_track_offset_unseen = !best.reach_estimated && !best.lag_estimated && offset_var > 0 &&
                                     best.along_track_offset_sigma_m > 2 * std::max(best.predicted_rmse_m, 0.01);
    if (best.along_track_offset_unseen) {
      const HeldOffsetPrior prior{std::hypot(speed * options.clock_sigma_s, c_t * options.sag_sigma),
                                  options.exact_share};
      const double offset_sq = HeldOffsetMeanSquare(best.along_track_offset_m, best.along_track_offset_sigma_m, prior);
      // (log k, lag) per metre of offset, split between them as the free fit sees them
      const Eigen::Vector2d per_metre = free_cov * along / offset_var;
      for (const Eigen::Matrix2d& shift : best.shift_per_reach_lag)
        unseen_var.push_back((shift * per_metre).squaredNorm() * offset_sq);
    }
  }
  if (!best.current_estimated) {
    for (double& var : held_current_var) var *= kHeldCurrentShare;
    AddKeyframeVariance(held_current_var, &best);
  }
  if (!unseen_var.empty()) best.unseen_offset_rmse_m = AddKeyframeVariance(unseen_var, &best);
  // The spread is over the splits of the shift along the track, the current
  // as decided: a current freed after the BICs held it would otherwise count
  // twice, once freed and once as the held candidates' distance from it
  // (predicted 0.20 m where the map was 0.09 m off; docs/GEOREF.md, "seventh pass").
  std::vector<WeighedFit> weighed;
  for (const ReachLagCandidate& c : candidates)
    if (c.current == best.current_estimated) weighed.push_back({&c.fit, c.bic});
  if (weighed.size() > 1) AddSelectionSpread(path, weighed, &best);
  return best;
}

double AddKeyframeVariance(const std::vector<double>& extra_variance_m2, TowedFitResult* fit) {
  const size_t n = fit->keyframe_sigma_m.size();
  if (extra_variance_m2.size() != n || n == 0) return 0;
  double sq = 0, extra = 0;
  for (size_t i = 0; i < n; ++i) {
    double& sigma = fit->keyframe_sigma_m[i];
    sigma = std::sqrt(sigma * sigma + extra_variance_m2[i]);
    sq += sigma * sigma;
    extra += extra_variance_m2[i];
  }
  fit->predicted_rmse_m = std::sqrt(sq / n);
  return std::sqrt(extra / n);
}

Similarity WakeStart(const SlamPath& path, const std::vector<double>& reach_m, const std::vector<double>& depth_m,
                     const BuoyTrack& buoy, double speed_mps) {
  const TimeSeries reach(path, Filled(reach_m, 1));
  const TimeSeries depth(path, Filled(depth_m, 0));
  std::vector<Eigen::Vector3d> from, to;
  std::vector<double> weights;
  const double t0 = path.time(0), t1 = path.time(path.size() - 1);
  const double speed = std::max(speed_mps, 0.05);
  for (const BuoyFix& f : buoy.fixes()) {
    const double t = f.time_s - reach.At(f.time_s) / speed;
    if (t < t0 || f.time_s > t1) continue;
    from.push_back(path.PositionAt(t));
    to.push_back({f.position_en_m.x(), f.position_en_m.y(), -depth.At(t)});
    weights.push_back(1);
  }
  if (from.size() < 3) return Similarity{};
  return FitSimilarity(from, to, weights);
}

}  // namespace seamap
