#pragma once
// The whole-survey navigation refinement's solver: one robust planar pose graph
// (docs: /work/shared/specs/visual-odometry-ekf.md section 3). Unknowns per frame
// are t = (E, N) in metres and heading psi in radians, clockwise from north.
// Rot(psi) = [[cos, sin], [-sin, cos]] acts on (E, N) column vectors; a seabed
// point seen by frame i at heading-free ground offset a_i is t_i + Rot(psi_i) a_i.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct PlanarPose {
  double east_m = 0, north_m = 0, heading_rad = 0;
};

// An image registration between frames i and j: a_i ~ dt + Rot(dheading) a_j for
// every matched point. The model predicts dt = Rot(-psi_i)(t_j - t_i) and
// dheading = psi_j - psi_i (compared modulo 2 pi).
struct PairConstraint {
  int i = 0, j = 0;  // frame indices into the navigation
  double dt_east_m = 0, dt_north_m = 0, dheading_rad = 0;
  // Covariance of (dt_east_m, dt_north_m, dheading_rad); symmetric positive definite.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  bool along_track = false;  // consecutive-ish pair vs cross-line/loop (for the report)
};

struct PoseGraphOptions {
  double nav_sigma_m = 0.05;                         // stated position noise sigma_n (floor 1 mm)
  double nav_drift_m_per_s = 1.0 / 60;               // stated drift rate rho (m/min / 60)
  double heading_sigma_rad = 0.0175;                 // stated heading noise (floor 0.01 deg)
  double pair_loss_scale = 3, prior_loss_scale = 3;  // CauchyLoss on pairs, HuberLoss on absolute priors
  double reject_chi2 = 11.34;  // pair blocks above this whitened squared norm are dropped, then re-solve
  int max_iterations = 100, threads = 2;

  // Throws InputError naming the first bad option (negative or non-finite noise,
  // non-positive loss scales, reject_chi2 <= 0, max_iterations or threads < 1).
  void Check() const;
};

struct PoseGraphResult {
  std::vector<PlanarPose> poses;           // refined, one per navigation pose; headings near the navigation's branch
  std::vector<bool> pair_rejected;         // per constraint
  std::vector<bool> nav_only;              // frames left without an accepted pair
  double cost_before = 0, cost_after = 0;  // Ceres costs: start of the first solve, end of the last
  int iterations = 0;                      // summed over the solves
  bool converged = false;                  // the last solve ended on a convergence test
  std::string linear_solver;               // e.g. "SPARSE_NORMAL_CHOLESKY/SUITE_SPARSE"; empty when no solve ran
};

// RMS over the pairs the graph kept of how far each pair's measured motion
// is from what the poses say, before (navigation) and after (solved), in mm;
// with how many pairs the graph rejected. RefineSurvey and the live refiner report it.
struct PairResidualRms {
  int rejected = 0;
  double before_mm = 0, after_mm = 0;
};
PairResidualRms PairResiduals(const std::vector<PairConstraint>& pairs, const std::vector<PlanarPose>& nav,
                              const PoseGraphResult& solved);

// nav: navigation poses with their times (seconds, non-decreasing); pairs: image
// constraints. Solves from the navigation, drops the pairs whose whitened squared
// norm then exceeds options.reject_chi2 and, if any, solves once more without them
// (from the first solution). Without accepted pairs the navigation comes back
// exactly. Residuals, losses and noise floors: the spec's section 3.
// Throws InputError for bad options, mismatched sizes, unsorted or non-finite
// times, out-of-range pair indices, or a covariance that is not positive definite.
PoseGraphResult SolvePoseGraph(const std::vector<PlanarPose>& nav, const std::vector<double>& time_s,
                               const std::vector<PairConstraint>& pairs, const PoseGraphOptions& options);

// The whitened squared norm r^T S^-1 r of a pair's residual at the given poses
// (no loss applied): what the rejection test compares with options.reject_chi2.
double PairWhitenedSquaredNorm(const PairConstraint& pair, const PlanarPose& pose_i, const PlanarPose& pose_j);

}  // namespace seamap
