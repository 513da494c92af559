#include "core/georef/fit_quality.h"

#include <cmath>

#include <Eigen/Dense>

namespace seamap {
namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// d(mapped point) / d(parameters) for a point p = s R (x - centroid).
Eigen::Matrix<double, 3, 7> Jacobian(const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 3, 7> j;
  j.block<3, 3>(0, 0) = -Skew(p);
  j.col(3) = p;
  j.block<3, 3>(0, 4) = Eigen::Matrix3d::Identity();
  return j;
}

}  // namespace

double FitUncertainty::HorizontalSigma(const Similarity& fit, const Eigen::Vector3d& slam) const {
  if (!ok) return 0;
  const Eigen::Matrix<double, 3, 7> j = Jacobian(fit.scale * fit.rotation * (slam - centroid_slam));
  const Eigen::Matrix3d cov = j * covariance * j.transpose();
  return std::sqrt(std::max(cov(0, 0) + cov(1, 1), 0.0));
}

FitUncertainty PredictUncertainty(const Similarity& fit, const std::vector<Eigen::Vector3d>& slam,
                                  const std::vector<double>& horizontal, const std::vector<double>& vertical) {
  FitUncertainty u;
  double total = 0;
  u.centroid_slam.setZero();
  for (size_t i = 0; i < slam.size(); ++i) {
    u.centroid_slam += horizontal[i] * slam[i];
    total += horizontal[i];
  }
  if (!(total > 0)) return u;
  u.centroid_slam /= total;
  Eigen::Matrix<double, 7, 7> information = Eigen::Matrix<double, 7, 7>::Zero();
  for (size_t i = 0; i < slam.size(); ++i) {
    const Eigen::Matrix<double, 3, 7> j = Jacobian(fit.scale * fit.rotation * (slam[i] - u.centroid_slam));
    const Eigen::Vector3d w(horizontal[i], horizontal[i], vertical[i]);
    information += j.transpose() * w.asDiagonal() * j;
  }
  Eigen::FullPivLU<Eigen::Matrix<double, 7, 7>> lu(information);
  if (!lu.isInvertible()) return u;
  u.covariance = lu.inverse();
  u.ok = true;
  for (int k = 0; k < 3; ++k) u.rotation_sigma_deg[k] = std::sqrt(std::max(u.covariance(k, k), 0.0)) * 180 / M_PI;
  u.scale_sigma = std::sqrt(std::max(u.covariance(3, 3), 0.0));
  for (int k = 0; k < 3; ++k) u.position_sigma_m[k] = std::sqrt(std::max(u.covariance(4 + k, 4 + k), 0.0));
  return u;
}

double EigenRatio(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights) {
  double total = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < points.size(); ++i) {
    mean += weights[i] * points[i];
    total += weights[i];
  }
  if (!(total > 0)) return 0;
  mean /= total;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < points.size(); ++i) cov += weights[i] * (points[i] - mean) * (points[i] - mean).transpose();
  const Eigen::Vector3d l = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov / total).eigenvalues();  // ascending
  return l(2) > 0 ? std::sqrt(std::max(l(1), 0.0) / l(2)) : 0;
}

}  // namespace seamap
