#include "core/georef/similarity.h"

#include <stdexcept>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace seamap {
namespace {

struct Moments {
  Eigen::Vector3d mu_x, mu_q;
  double var_x = 0;
  Eigen::Matrix3d cov;  // sum w (q - mu_q)(x - mu_x)^T / W
};

Moments WeightedMoments(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                        const std::vector<double>& weights) {
  if (from.size() != to.size() || from.size() != weights.size() || from.empty())
    throw std::invalid_argument("similarity fit: point and weight counts differ or are zero");
  double total = 0;
  Moments m;
  m.mu_x.setZero();
  m.mu_q.setZero();
  for (size_t i = 0; i < from.size(); ++i) {
    if (!(weights[i] >= 0)) throw std::invalid_argument("similarity fit: negative weight");
    total += weights[i];
    m.mu_x += weights[i] * from[i];
    m.mu_q += weights[i] * to[i];
  }
  if (!(total > 0)) throw std::invalid_argument("similarity fit: weights sum to zero");
  m.mu_x /= total;
  m.mu_q /= total;
  m.cov.setZero();
  for (size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector3d dx = from[i] - m.mu_x;
    m.var_x += weights[i] * dx.squaredNorm();
    m.cov += weights[i] * (to[i] - m.mu_q) * dx.transpose();
  }
  m.var_x /= total;
  m.cov /= total;
  return m;
}

// R = U S V^T with S = diag(1, 1, det U det V); returns tr(D S) too.
Eigen::Matrix3d GuardedRotation(const Eigen::Matrix3d& cov, double* trace_ds) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s(1, 1, 1);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) s(2) = -1;
  if (trace_ds) *trace_ds = svd.singularValues().dot(s);
  return svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
}

}  // namespace

Similarity FitSimilarity(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                         const std::vector<double>& weights) {
  const Moments m = WeightedMoments(from, to, weights);
  if (!(m.var_x > 0)) throw std::invalid_argument("similarity fit: all points coincide");
  Similarity sim;
  double trace_ds = 0;
  sim.rotation = GuardedRotation(m.cov, &trace_ds);
  sim.scale = trace_ds / m.var_x;
  sim.translation = m.mu_q - sim.scale * sim.rotation * m.mu_x;
  return sim;
}

Similarity FitRigid(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                    const std::vector<double>& weights, double scale) {
  const Moments m = WeightedMoments(from, to, weights);
  Similarity sim;
  sim.scale = scale;
  sim.rotation = GuardedRotation(m.cov, nullptr);
  sim.translation = m.mu_q - scale * sim.rotation * m.mu_x;
  return sim;
}

}  // namespace seamap
