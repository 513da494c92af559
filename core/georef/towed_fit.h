#pragma once
// The similarity, the tether's reach and the buoy's way of following,
// fitted jointly to every GPS fix (docs/GEOREF.md, "Method: --method tether").
//
// For parameters theta = (rotation, scale, translation, reach factor k,
// wake share a, current c, the fixes' lag tau) the SLAM path is mapped into
// the working frame and a model buoy is towed behind it: (1 - a) of a buoy
// pulled along a taut tether (a tractrix; it cuts the corners; the current
// carries it, so it trails along the vehicle's motion through the water)
// plus a of a buoy running in the vehicle's wake k c_t back along its path
// (it goes round them). Both agree on straight legs and differ after turns,
// which is where the data tell them apart. Each fix, stamped t, is compared
// with the model buoy at t - tau (a clock offset, a slow receiver); each
// keyframe's height with -depth. Gauss-Newton with Levenberg damping,
// Huber weights, fixes beyond 5 sigma dropped; while the model says the
// tether is slack (and while the buoy settles after the start) the fixes
// keep a widened noise, sigma^2 + sigma_model^2, sigma_model estimated from
// their own scatter, instead of being dropped; while it settles, plus what
// its unknown start may leave where the path turns from the start, up to a
// reach times exp(-travel / reach). The towing direction is
// never read from a window of fixes or the camera's axes: it is the mapped
// path's own motion through the model.
//
// The error estimate: the parameters' covariance from the normal equations,
// times the residuals' variance factor and their correlation in time (batch
// means), propagated to every keyframe, plus the keyframe's SLAM noise, plus
// a quarter of what freeing a current held at zero would add, plus what an
// offset along the track the fixes cannot see may still do.
#include <vector>

#include <Eigen/Core>

#include "core/georef/buoy_track.h"
#include "core/georef/similarity.h"
#include "core/georef/slam_path.h"

namespace seamap {

struct TowedFitOptions {
  double step_s = 0.1;              // the model buoy's time step
  double huber_k = 2;               // in sigmas
  double outlier_sigmas = 5;        // fixes beyond this are dropped (multipath)
  double reach_prior_sigma = 0.15;  // relative, on k (1 = the straight tether's reach) ...
  double reach_significance = 3;    // ... kept at 1 unless the data put it this many sigmas away
  double wake_prior_mean = 0.5;     // a, kept within [0, 1] ...
  double wake_prior_sigma = 1;      // ... and pure (0 or 1) unless the data put it 3 sigmas away
  double current_prior_mps = 0.1;   // on each component of a current carrying the buoy, about 0;
                                    // kept at 0 unless the data put it 3 sigmas away
  double lag_prior_s = 10;          // on the fixes' lag behind the keyframes' clock, about 0; kept at 0 likewise
  // What the fixes cannot see of the buoy's offset along the track (a spiral,
  // legs all flown one way) comes from these (held_offset.h): how well the
  // fixes' clock is known to agree with the keyframes', how much the tether
  // may sag (a share of its reach), and the chance that neither is there.
  double clock_sigma_s = 1;
  double sag_sigma = 0.02;
  double exact_share = 0.5;
  double depth_sigma_m = 0.05;  // of a keyframe's depth
  double settle_reaches = 2;    // fixes within this many reaches of travel after the start: widened
  double batch_s = 30;          // batch length for the residuals' correlation
  int max_iterations = 30;
  int min_taut_fixes = 10;
};

struct TowedFitResult {
  bool ok = false;
  Similarity fit;
  double reach_factor = 1, reach_factor_sigma = 0;
  bool reach_estimated = false;                           // else the straight tether's reach (k = 1)
  bool wake_estimated = false;                            // else a pure tractrix (a = 0) or wake follower (a = 1)
  double wake_share = 0, wake_share_sigma = 0;            // 0 = tractrix, 1 = the vehicle's wake
  Eigen::Vector2d current_mps = Eigen::Vector2d::Zero();  // east, north
  Eigen::Matrix2d current_covariance = Eigen::Matrix2d::Zero();
  bool current_estimated = false;
  double lag_s = 0, lag_sigma_s = 0;  // a fix stamped t shows the buoy at t - lag
  bool lag_estimated = false;
  Eigen::Matrix2d reach_lag_covariance = Eigen::Matrix2d::Zero();  // of (log k, tau) in this fit
  // The fit with every parameter free: reach and lag as the data alone see
  // them (for a buoy in the wake both are one shift along the track).
  double free_reach_factor = 1, free_lag_s = 0;
  Eigen::Matrix2d free_reach_lag_covariance = Eigen::Matrix2d::Zero();  // of (log k, tau)
  // Per keyframe, how this fit's map moves (east, north; m) per unit of
  // log k (column 0) and per second of lag (column 1), the parameters it
  // estimates following: what a reach or a lag held at its default but not
  // there does to the map.
  std::vector<Eigen::Matrix2d> shift_per_reach_lag;
  std::vector<bool> keyframe_taut;       // the model's tether at each keyframe's time
  std::vector<double> keyframe_sigma_m;  // predicted horizontal error (2D RMS) per keyframe
  double predicted_rmse_m = 0;           // RMS of keyframe_sigma_m
  double gps_bound_rmse_m = 0;           // the same from the taut fixes' GPS noise alone, k and a known
  double model_bound_rmse_m = 0;         // the same from every fix's GPS noise, the parameters this fit frees unknown
  double variance_factor = 1;            // chi^2 / dof of the taut fixes (at least 1)
  double correlation_factor = 1;         // variance of batch means over white noise's (at least 1)
  double taut_model_sigma_m = 0;         // model noise added to taut fixes (waves, an imperfect model)
  double slack_model_sigma_m = 0;        // and to the others
  double residual_rms_m = 0;             // of the taut fixes kept
  // The buoy's offset along the track, c_t (k - 1) + |v| lag, as the fit
  // with everything free sees it; where it is seen worse than twice the
  // estimate's error and reach and lag are held (unseen), what it may be
  // under the prior (held_offset.h) moves the held map by
  // unseen_offset_rmse_m (RMS over the keyframes, in predicted_rmse_m).
  double along_track_offset_m = 0, along_track_offset_sigma_m = 0;
  bool along_track_offset_unseen = false;
  double unseen_offset_rmse_m = 0;
  // Where reach and lag trade with each other, the three fits (reach, lag,
  // both) are compared by BIC; this is the RMS spread (over the keyframes) of
  // their maps about the kept one, weighted by exp(-dBIC / 2); in predicted_rmse_m.
  double selection_spread_rmse_m = 0;
  double robust_cost = 0;  // Huber's, twice, of every fix against its GPS sigma (chi-square units)
  int cost_observations = 0;
  int fixes = 0, taut_fixes = 0, outliers = 0, iterations = 0;
  Eigen::Vector2d along_cross_bias_m = Eigen::Vector2d::Zero();  // mean taut residual along / across towing
};

// Adds extra_variance_m2[i] (m^2) to keyframe i's predicted error and
// recomputes predicted_rmse_m from them: the estimate's additions (a held
// current's share, the candidate fits' spread, an unseen offset along the
// track). Returns the addition's RMS over the keyframes (m); nothing, and 0,
// when the sizes differ.
double AddKeyframeVariance(const std::vector<double>& extra_variance_m2, TowedFitResult* fit);

// reach_m: per keyframe, the straight tether's horizontal reach (0 where
// unknown); depth_m: per keyframe, NAN where unknown. slam_sigma: the SLAM
// noise per axis in SLAM units. start: a rough similarity (any fit within a
// few metres and degrees).
TowedFitResult FitTowedBuoy(const SlamPath& path, const std::vector<double>& reach_m,
                            const std::vector<double>& depth_m, const BuoyTrack& buoy, const Similarity& start,
                            double slam_sigma, const TowedFitOptions& options);

// A start for FitTowedBuoy without any taut selection: each fix paired with
// the SLAM position reach / speed earlier (the buoy in the wake), fitted by
// weighted Umeyama with the depths. speed_mps: the buoy's median speed.
Similarity WakeStart(const SlamPath& path, const std::vector<double>& reach_m, const std::vector<double>& depth_m,
                     const BuoyTrack& buoy, double speed_mps);

}  // namespace seamap
