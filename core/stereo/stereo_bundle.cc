#include "core/stereo/stereo_bundle.h"

#include <cmath>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

namespace seamap {
namespace {

struct StereoReprojection {
  StereoReprojection(const RectifiedRig& rig, const BundleObservation& o, double sigma_px)
      : f(rig.f),
        cx(rig.cx),
        cy(rig.cy),
        b(rig.baseline_m),
        ul(o.left_px.x),
        vl(o.left_px.y),
        ur(o.right_px.x),
        vr(o.right_px.y),
        inv_sigma(1 / sigma_px) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) rect[3 * r + c] = rig.rect_from_left(r, c);
  }
  // pose: object_from_camera as (rotation vector, translation).
  template <typename T>
  bool Project(const T* pose, const T* point, T* xyz_rect) const {
    const T d[3] = {point[0] - pose[3], point[1] - pose[4], point[2] - pose[5]};
    const T minus_w[3] = {-pose[0], -pose[1], -pose[2]};
    T cam[3];
    ceres::AngleAxisRotatePoint(minus_w, d, cam);
    for (int r = 0; r < 3; ++r)
      xyz_rect[r] = rect[3 * r] * cam[0] + rect[3 * r + 1] * cam[1] + rect[3 * r + 2] * cam[2];
    return xyz_rect[2] > T(1e-6);
  }
  double f, cx, cy, b, ul, vl, ur, vr, inv_sigma;
  double rect[9];
};

struct StereoCost : StereoReprojection {
  using StereoReprojection::StereoReprojection;
  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    if (!Project(pose, point, p)) return false;
    const T inv_z = T(1) / p[2];
    const T v = f * p[1] * inv_z + cy;
    residual[0] = (f * p[0] * inv_z + cx - ul) * inv_sigma;
    residual[1] = (v - vl) * inv_sigma;
    residual[2] = (f * (p[0] - b) * inv_z + cx - ur) * inv_sigma;
    residual[3] = (v - vr) * inv_sigma;
    return true;
  }
};

struct LeftCost : StereoReprojection {
  using StereoReprojection::StereoReprojection;
  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T p[3];
    if (!Project(pose, point, p)) return false;
    const T inv_z = T(1) / p[2];
    residual[0] = (f * p[0] * inv_z + cx - ul) * inv_sigma;
    residual[1] = (f * p[1] * inv_z + cy - vl) * inv_sigma;
    return true;
  }
};

// Whitened prior: L^T (x - mean) with L L^T = inverse covariance.
struct PointPrior {
  PointPrior(const Eigen::Vector3d& mean, const Eigen::Matrix3d& cov) : mean(mean) {
    const Eigen::Matrix3d info = cov.inverse();
    sqrt_info = Eigen::LLT<Eigen::Matrix3d>(info).matrixL().transpose();
  }
  template <typename T>
  bool operator()(const T* point, T* residual) const {
    const T d[3] = {point[0] - mean[0], point[1] - mean[1], point[2] - mean[2]};
    for (int r = 0; r < 3; ++r) residual[r] = sqrt_info(r, 0) * d[0] + sqrt_info(r, 1) * d[1] + sqrt_info(r, 2) * d[2];
    return true;
  }
  Eigen::Vector3d mean;
  Eigen::Matrix3d sqrt_info;
};

// Relative pose prior: the measured from_camera_from_to_camera against the
// poses' own, rotation (angle-axis of the difference) and translation.
struct MotionPrior {
  explicit MotionPrior(const BundleMotion& m) : inv_sigma_m(1 / m.sigma_m), inv_sigma_rad(1 / m.sigma_rad) {
    const Eigen::Matrix<double, 6, 1> v = RigidToVector(m.from_camera_from_to_camera.inverse());
    for (int i = 0; i < 6; ++i) measured_inverse[i] = v[i];
  }
  template <typename T>
  bool operator()(const T* from, const T* to, T* residual) const {
    // from_camera_from_to_camera = R_from^T (R_to x + t_to - t_from)
    T r_from[9], r_to[9], r_m[9];
    ceres::AngleAxisToRotationMatrix(from, ceres::RowMajorAdapter3x3(r_from));
    ceres::AngleAxisToRotationMatrix(to, ceres::RowMajorAdapter3x3(r_to));
    const T w_m[3] = {T(measured_inverse[0]), T(measured_inverse[1]), T(measured_inverse[2])};
    ceres::AngleAxisToRotationMatrix(w_m, ceres::RowMajorAdapter3x3(r_m));
    // rel = R_from^T R_to; error = measured^-1 * rel.
    T rel[9], err[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        rel[3 * i + j] = T(0);
        for (int k = 0; k < 3; ++k) rel[3 * i + j] += r_from[3 * k + i] * r_to[3 * k + j];
      }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        err[3 * i + j] = T(0);
        for (int k = 0; k < 3; ++k) err[3 * i + j] += r_m[3 * i + k] * rel[3 * k + j];
      }
    T w_err[3];
    ceres::RotationMatrixToAngleAxis(ceres::RowMajorAdapter3x3(static_cast<const T*>(err)), w_err);
    T t_rel[3];
    const T d[3] = {to[3] - from[3], to[4] - from[4], to[5] - from[5]};
    for (int i = 0; i < 3; ++i)
      t_rel[i] = r_from[3 * 0 + i] * d[0] + r_from[3 * 1 + i] * d[1] + r_from[3 * 2 + i] * d[2];
    // measured^-1 * (R, t): R_m t_rel + t_m
    for (int i = 0; i < 3; ++i) {
      residual[i] = w_err[i] * inv_sigma_rad;
      T t = T(measured_inverse[3 + i]);
      for (int k = 0; k < 3; ++k) t += r_m[3 * i + k] * t_rel[k];
      residual[3 + i] = t * inv_sigma_m;
    }
    return true;
  }
  double measured_inverse[6];
  double inv_sigma_m, inv_sigma_rad;
};

}  // namespace

bool ProjectToPair(const RectifiedRig& rig, const Rigid& object_from_camera, const Eigen::Vector3d& xyz_object,
                   cv::Point2d* left_px, cv::Point2d* right_px) {
  return rig.Project(object_from_camera.inverse() * xyz_object, left_px, right_px);
}

BundleResult SolveBundle(BundleProblem* problem, const RectifiedRig& rig, int covariance_of_pose, int max_iterations) {
  BundleResult result;
  const size_t n_poses = problem->poses.size();
  std::vector<std::array<double, 6>> pose_params(n_poses);
  for (size_t k = 0; k < n_poses; ++k) {
    const auto v = RigidToVector(problem->poses[k]);
    for (int i = 0; i < 6; ++i) pose_params[k][i] = v[i];
  }
  std::vector<std::array<double, 3>> point_params(problem->points.size());
  for (size_t k = 0; k < problem->points.size(); ++k)
    for (int i = 0; i < 3; ++i) point_params[k][i] = problem->points[k].xyz[i];

  ceres::Problem::Options problem_options;
  ceres::Problem ceres_problem(problem_options);
  const double sigma = std::max(1e-3, problem->sigma_px);
  std::vector<bool> pose_used(n_poses, false), point_used(problem->points.size(), false);
  for (const BundleObservation& o : problem->observations) {
    ceres::LossFunction* loss = new ceres::HuberLoss(2.0);
    if (o.has_right)
      ceres_problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<StereoCost, 4, 6, 3>(new StereoCost(rig, o, sigma)), loss,
          pose_params[o.pose].data(), point_params[o.point].data());
    else
      ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LeftCost, 2, 6, 3>(new LeftCost(rig, o, sigma)),
                                     loss, pose_params[o.pose].data(), point_params[o.point].data());
    pose_used[o.pose] = point_used[o.point] = true;
  }
  for (size_t k = 0; k < problem->points.size(); ++k) {
    const BundlePoint& p = problem->points[k];
    if (!point_used[k]) continue;
    if (p.has_prior)
      ceres_problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<PointPrior, 3, 3>(new PointPrior(p.prior_xyz, p.prior_cov)), nullptr,
          point_params[k].data());
    if (p.fixed) ceres_problem.SetParameterBlockConstant(point_params[k].data());
  }
  for (const BundleMotion& m : problem->motions) {
    if (m.from_pose < 0 || m.to_pose < 0 || m.from_pose >= static_cast<int>(n_poses) ||
        m.to_pose >= static_cast<int>(n_poses) || !pose_used[m.from_pose] || !pose_used[m.to_pose])
      continue;
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<MotionPrior, 6, 6, 6>(new MotionPrior(m)), nullptr,
                                   pose_params[m.from_pose].data(), pose_params[m.to_pose].data());
  }
  for (size_t k = 0; k < n_poses; ++k)
    if (pose_used[k] && k < problem->pose_fixed.size() && problem->pose_fixed[k])
      ceres_problem.SetParameterBlockConstant(pose_params[k].data());

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_SCHUR;
  options.max_num_iterations = max_iterations;
  options.num_threads = 1;
  options.function_tolerance = 1e-10;
  options.parameter_tolerance = 1e-10;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &ceres_problem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;

  for (size_t k = 0; k < n_poses; ++k) {
    Eigen::Matrix<double, 6, 1> v;
    for (int i = 0; i < 6; ++i) v[i] = pose_params[k][i];
    problem->poses[k] = RigidFromVector(v);
  }
  for (size_t k = 0; k < problem->points.size(); ++k)
    problem->points[k].xyz = Eigen::Vector3d(point_params[k][0], point_params[k][1], point_params[k][2]);

  double sum_sq = 0;
  int count = 0;
  result.residual_px.reserve(problem->observations.size());
  for (const BundleObservation& o : problem->observations) {
    cv::Point2d l, r;
    double worst = 1e9;
    if (ProjectToPair(rig, problem->poses[o.pose], problem->points[o.point].xyz, &l, &r)) {
      const double el = cv::norm(l - o.left_px), er = o.has_right ? cv::norm(r - o.right_px) : 0;
      sum_sq += el * el + er * er;
      count += o.has_right ? 4 : 2;
      worst = std::max(el, er);
    }
    result.residual_px.push_back(worst);
  }
  result.rms_px = count ? std::sqrt(sum_sq / count) : 0;
  const int m = summary.num_residuals_reduced, p = summary.num_effective_parameters_reduced;
  result.sigma_scale = m > p ? std::sqrt(2 * summary.final_cost / (m - p)) : 1;

  if (covariance_of_pose >= 0 && covariance_of_pose < static_cast<int>(n_poses) && pose_used[covariance_of_pose] &&
      !(covariance_of_pose < static_cast<int>(problem->pose_fixed.size()) && problem->pose_fixed[covariance_of_pose])) {
    ceres::Covariance::Options cov_options;
    cov_options.algorithm_type = ceres::SPARSE_QR;
    cov_options.num_threads = 1;
    ceres::Covariance covariance(cov_options);
    const double* block = pose_params[covariance_of_pose].data();
    std::vector<std::pair<const double*, const double*>> blocks{{block, block}};
    if (covariance.Compute(blocks, &ceres_problem)) {
      double c[36];
      covariance.GetCovarianceBlock(block, block, c);
      result.covariance = Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(c);
      result.covariance *= result.sigma_scale * result.sigma_scale;
      result.has_covariance = true;
    }
  }
  return result;
}

}  // namespace seamap
