#include "core/trajectory/pose_graph.h"

#include <array>
#include <cmath>
#include <memory>
#include <string>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "core/trajectory/ground_offsets.h"
#include "core/trajectory/nav_priors.h"
#include "core/util/error.h"

namespace seamap {
namespace {

using PoseBlock = std::array<double, 3>;  // [east_m, north_m, heading_rad], one Ceres parameter block

// S^-1/2 [Rot(-psi_i)(t_j - t_i) - dt ; wrap(psi_j - psi_i - dpsi)]. The whitening
// is L^-1 with S = L L^T: it differs from the symmetric root by a rotation, which
// leaves the squared norm, and so the loss, unchanged.
struct PairResidual {
  Eigen::Vector3d measured;  // dt_east_m, dt_north_m, dheading_rad
  Eigen::Matrix3d whitening;

  template <typename T>
  bool operator()(const T* pose_i, const T* pose_j, T* residual) const {
    using std::cos;
    using std::sin;
    const T d_east_m = pose_j[0] - pose_i[0];
    const T d_north_m = pose_j[1] - pose_i[1];
    const T c = cos(pose_i[2]), s = sin(pose_i[2]);
    Eigen::Matrix<T, 3, 1> r;
    r(0) = c * d_east_m - s * d_north_m - measured(0);  // Rot(-psi) = [[c, -s], [s, c]]
    r(1) = s * d_east_m + c * d_north_m - measured(1);
    r(2) = WrapAngle(pose_j[2] - pose_i[2] - measured(2));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = whitening.cast<T>() * r;
    return true;
  }
};

// A separate block from the position so that a compass glitch does not down-weight the fix.
struct NavHeadingResidual {
  double heading_rad, inv_sigma_rad;

  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    residual[0] = WrapAngle(pose[2] - heading_rad) * inv_sigma_rad;
    return true;
  }
};

bool Finite(double value) {
  return std::isfinite(value);
}

void RequirePositiveFinite(double value, const char* name) {
  if (!(value > 0) || !Finite(value)) {
    throw InputError("", 0, name, "expected a positive finite number, got " + std::to_string(value));
  }
}

void RequireNonNegativeFinite(double value, const char* name) {
  if (!(value >= 0) || !Finite(value)) {
    throw InputError("", 0, name, "expected a finite number >= 0, got " + std::to_string(value));
  }
}

std::string PairField(size_t k, const char* member) {
  return "pairs[" + std::to_string(k) + "]." + member;
}

void CheckNavigation(const std::vector<PlanarPose>& nav, const std::vector<double>& time_s) {
  if (time_s.size() != nav.size()) {
    throw InputError("", 0, "time_s",
                     "expected one time per navigation pose (" + std::to_string(nav.size()) + "), got " +
                         std::to_string(time_s.size()));
  }
  for (size_t i = 0; i < nav.size(); ++i) {
    if (!Finite(nav[i].east_m) || !Finite(nav[i].north_m) || !Finite(nav[i].heading_rad)) {
      throw InputError("", 0, "nav[" + std::to_string(i) + "]", "expected finite east, north and heading");
    }
    if (!Finite(time_s[i]) || (i > 0 && time_s[i] < time_s[i - 1])) {
      throw InputError("", 0, "time_s[" + std::to_string(i) + "]",
                       "expected finite, non-decreasing times, got " + std::to_string(time_s[i]));
    }
  }
}

// Checks each pair and returns its whitening L^-1 (S = L L^T).
std::vector<Eigen::Matrix3d> CheckPairs(const std::vector<PairConstraint>& pairs, size_t frame_count) {
  std::vector<Eigen::Matrix3d> whitening;
  whitening.reserve(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    const PairConstraint& pair = pairs[k];
    for (int index : {pair.i, pair.j}) {
      if (index < 0 || static_cast<size_t>(index) >= frame_count) {
        throw InputError(
            "", 0, PairField(k, index == pair.i ? "i" : "j"),
            "expected a frame index in [0, " + std::to_string(frame_count) + "), got " + std::to_string(index));
      }
    }
    if (pair.i == pair.j) throw InputError("", 0, PairField(k, "j"), "expected two different frames");
    if (!Finite(pair.dt_east_m) || !Finite(pair.dt_north_m) || !Finite(pair.dheading_rad)) {
      throw InputError("", 0, PairField(k, "dt_east_m"), "expected a finite motion");
    }
    const Eigen::Matrix3d& s = pair.covariance;
    const bool symmetric = (s - s.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * s.cwiseAbs().maxCoeff();
    Eigen::LLT<Eigen::Matrix3d> llt(s);
    if (!s.allFinite() || !symmetric || llt.info() != Eigen::Success ||
        !(llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 0)) {
      throw InputError("", 0, PairField(k, "covariance"), "expected a symmetric positive definite 3x3 matrix");
    }
    const Eigen::Matrix3d lower = llt.matrixL();
    whitening.push_back(lower.inverse());
  }
  return whitening;
}

PairResidual MakePairResidual(const PairConstraint& pair, const Eigen::Matrix3d& whitening) {
  return PairResidual{Eigen::Vector3d(pair.dt_east_m, pair.dt_north_m, pair.dheading_rad), whitening};
}

std::vector<PoseBlock> BlocksFromNav(const std::vector<PlanarPose>& nav) {
  std::vector<PoseBlock> blocks(nav.size());
  for (size_t i = 0; i < nav.size(); ++i) blocks[i] = {nav[i].east_m, nav[i].north_m, nav[i].heading_rad};
  return blocks;
}

// SPARSE_NORMAL_CHOLESKY when Ceres has a sparse library, else the iterative CGNR:
// dense normal equations of 720 frames take minutes per iteration.
void ChooseLinearSolver(ceres::Solver::Options* solver, std::string* name) {
  solver->linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  for (ceres::SparseLinearAlgebraLibraryType library : {ceres::SUITE_SPARSE, ceres::EIGEN_SPARSE, ceres::CX_SPARSE}) {
    if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(library)) {
      solver->sparse_linear_algebra_library_type = library;
      *name = std::string("SPARSE_NORMAL_CHOLESKY/") + ceres::SparseLinearAlgebraLibraryTypeToString(library);
      return;
    }
  }
  solver->linear_solver_type = ceres::CGNR;
  solver->preconditioner_type = ceres::JACOBI;
  *name = "CGNR/JACOBI";
}

struct SolveOutcome {
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
  bool converged = false;
};

// One Ceres solve of the whole graph with the pairs flagged in `use`, from and into `blocks`.
SolveOutcome SolveOnce(const std::vector<PlanarPose>& nav, const std::vector<double>& time_s,
                       const std::vector<PairConstraint>& pairs, const std::vector<Eigen::Matrix3d>& whitening,
                       const std::vector<bool>& use, const PoseGraphOptions& options, std::vector<PoseBlock>* blocks,
                       std::string* linear_solver) {
  const double sigma_n_m = std::max(options.nav_sigma_m, kNavSigmaFloorM);
  const double sigma_psi_rad = std::max(options.heading_sigma_rad, kHeadingSigmaFloorRad);
  const double rho_m_per_s = options.nav_drift_m_per_s;

  // Losses are shared by many blocks; the problem must not delete them.
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss pair_loss(options.pair_loss_scale);
  ceres::HuberLoss prior_loss(options.prior_loss_scale);

  for (auto& block : *blocks) problem.AddParameterBlock(block.data(), 3);
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (!use[k]) continue;
    auto* cost = new ceres::AutoDiffCostFunction<PairResidual, 3, 3, 3>(
        new PairResidual(MakePairResidual(pairs[k], whitening[k])));
    problem.AddResidualBlock(cost, &pair_loss, (*blocks)[pairs[k].i].data(), (*blocks)[pairs[k].j].data());
  }
  for (size_t i = 0; i < nav.size(); ++i) {
    const double tau_s = time_s[i] - time_s[0];
    const double sigma_abs_m = std::hypot(sigma_n_m, rho_m_per_s * tau_s);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<NavPositionResidual, 2, 3>(
                                 new NavPositionResidual{nav[i].east_m, nav[i].north_m, 1 / sigma_abs_m}),
                             &prior_loss, (*blocks)[i].data());
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<NavHeadingResidual, 1, 3>(
                                 new NavHeadingResidual{nav[i].heading_rad, 1 / sigma_psi_rad}),
                             &prior_loss, (*blocks)[i].data());
    if (i + 1 == nav.size()) continue;
    const double dt_s = time_s[i + 1] - time_s[i];
    const double sigma_rel_m = std::sqrt(2 * sigma_n_m * sigma_n_m + std::pow(rho_m_per_s * dt_s, 2));
    auto* relative = new NavRelativeResidual<2>{nav[i + 1].east_m - nav[i].east_m, nav[i + 1].north_m - nav[i].north_m,
                                                nav[i + 1].heading_rad - nav[i].heading_rad, 1 / sigma_rel_m,
                                                1 / (std::sqrt(2.0) * sigma_psi_rad)};
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<NavRelativeResidual<2>, 3, 3, 3>(relative), nullptr,
                             (*blocks)[i].data(), (*blocks)[i + 1].data());
  }

  ceres::Solver::Options solver;
  ChooseLinearSolver(&solver, linear_solver);
  solver.num_threads = options.threads;
  solver.max_num_iterations = options.max_iterations;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  // Image pairs are often a thousand times tighter than the navigation; the
  // defaults would stop while the shape is still settling at the 0.1 mm level.
  solver.function_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  SolveOutcome outcome;
  outcome.initial_cost = summary.initial_cost;
  outcome.final_cost = summary.final_cost;
  outcome.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  outcome.converged = summary.termination_type == ceres::CONVERGENCE;
  return outcome;
}

}  // namespace

void PoseGraphOptions::Check() const {
  RequireNonNegativeFinite(nav_sigma_m, "nav_sigma_m");
  RequireNonNegativeFinite(nav_drift_m_per_s, "nav_drift_m_per_s");
  RequireNonNegativeFinite(heading_sigma_rad, "heading_sigma_rad");
  RequirePositiveFinite(pair_loss_scale, "pair_loss_scale");
  RequirePositiveFinite(prior_loss_scale, "prior_loss_scale");
  if (!(reject_chi2 > 0)) {  // +inf allowed: never reject
    throw InputError("", 0, "reject_chi2", "expected a positive number, got " + std::to_string(reject_chi2));
  }
  if (max_iterations < 1) {
    throw InputError("", 0, "max_iterations", "expected at least 1, got " + std::to_string(max_iterations));
  }
  if (threads < 1) throw InputError("", 0, "threads", "expected at least 1, got " + std::to_string(threads));
}

double PairWhitenedSquaredNorm(const PairConstraint& pair, const PlanarPose& pose_i, const PlanarPose& pose_j) {
  const std::vector<Eigen::Matrix3d> whitening = CheckPairs({pair}, std::max(pair.i, pair.j) + 1);
  const double block_i[3] = {pose_i.east_m, pose_i.north_m, pose_i.heading_rad};
  const double block_j[3] = {pose_j.east_m, pose_j.north_m, pose_j.heading_rad};
  double residual[3];
  MakePairResidual(pair, whitening[0])(block_i, block_j, residual);
  return residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2];
}

PoseGraphResult SolvePoseGraph(const std::vector<PlanarPose>& nav, const std::vector<double>& time_s,
                               const std::vector<PairConstraint>& pairs, const PoseGraphOptions& options) {
  options.Check();
  CheckNavigation(nav, time_s);
  const std::vector<Eigen::Matrix3d> whitening = CheckPairs(pairs, nav.size());

  PoseGraphResult result;
  result.poses = nav;
  result.pair_rejected.assign(pairs.size(), false);
  result.converged = true;  // nothing to solve is a solved problem

  std::vector<bool> use(pairs.size(), true);
  if (!pairs.empty()) {
    std::vector<PoseBlock> blocks = BlocksFromNav(nav);
    SolveOutcome first = SolveOnce(nav, time_s, pairs, whitening, use, options, &blocks, &result.linear_solver);
    result.cost_before = first.initial_cost;
    result.cost_after = first.final_cost;
    result.iterations = first.iterations;
    result.converged = first.converged;

    bool any_rejected = false, any_accepted = false;
    for (size_t k = 0; k < pairs.size(); ++k) {
      double residual[3];
      MakePairResidual(pairs[k], whitening[k])(blocks[pairs[k].i].data(), blocks[pairs[k].j].data(), residual);
      const double chi2 = residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2];
      use[k] = !(chi2 > options.reject_chi2);
      result.pair_rejected[k] = !use[k];
      any_rejected |= !use[k];
      any_accepted |= use[k];
    }

    // The second solve starts from the first's result: already in the right basin,
    // it takes a few iterations where a restart from the navigation takes a dozen.
    if (any_rejected) {
      if (any_accepted) {
        SolveOutcome second = SolveOnce(nav, time_s, pairs, whitening, use, options, &blocks, &result.linear_solver);
        result.cost_after = second.final_cost;
        result.iterations += second.iterations;
        result.converged = second.converged;
      } else {
        result.cost_after = 0;  // priors alone: the navigation is their exact minimum
        result.converged = true;
      }
    }
    if (any_accepted) {
      for (size_t i = 0; i < nav.size(); ++i) result.poses[i] = {blocks[i][0], blocks[i][1], blocks[i][2]};
    }
  }

  result.nav_only.assign(nav.size(), true);
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (use[k]) result.nav_only[pairs[k].i] = result.nav_only[pairs[k].j] = false;
  }
  return result;
}

PairResidualRms PairResiduals(const std::vector<PairConstraint>& pairs, const std::vector<PlanarPose>& nav,
                              const PoseGraphResult& solved) {
  // How far a pair's measured motion (in the first frame's axes) is from what the poses say, metres.
  auto disagreement = [](const PairConstraint& c, const PlanarPose& a, const PlanarPose& b) {
    const cv::Point2d predicted = RotateClockwise({b.east_m - a.east_m, b.north_m - a.north_m}, -a.heading_rad);
    return std::hypot(predicted.x - c.dt_east_m, predicted.y - c.dt_north_m);
  };
  PairResidualRms r;
  double before = 0, after = 0;
  int kept = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (solved.pair_rejected[k]) {
      ++r.rejected;
      continue;
    }
    const PairConstraint& c = pairs[k];
    before += std::pow(disagreement(c, nav[c.i], nav[c.j]), 2);
    after += std::pow(disagreement(c, solved.poses[c.i], solved.poses[c.j]), 2);
    ++kept;
  }
  if (kept) {
    r.before_mm = 1000 * std::sqrt(before / kept);
    r.after_mm = 1000 * std::sqrt(after / kept);
  }
  return r;
}

}  // namespace seamap
