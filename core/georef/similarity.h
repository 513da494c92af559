#pragma once
// Similarity transforms y = s R x + t between SLAM coordinates and the
// working frame (metres east, north, up), and their closed-form fits: the
// weighted Umeyama solution and the paper's rigid SVD (Kabsch), both with the
// reflection guard (a mirror image is never a valid answer).
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct Similarity {
  double scale = 1;                                        // metres per SLAM unit
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // SLAM axes -> east, north, up
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   // metres
  Eigen::Vector3d Apply(const Eigen::Vector3d& x) const { return scale * (rotation * x) + translation; }
};

// Minimises sum w_i |q_i - (s R x_i + t)|^2 (Umeyama 1991, weighted):
// C = sum w (q - mu_q)(x - mu_x)^T / W = U D V^T, S = diag(1, 1, det U det V),
// R = U S V^T, s = tr(D S) / var_x, t = mu_q - s R mu_x. The guard uses
// det U det V, not det C: C is singular for coplanar points.
// Requires from.size() == to.size() == weights.size(), weights >= 0 with a
// positive sum, and points not all equal (var_x > 0); throws
// std::invalid_argument otherwise.
Similarity FitSimilarity(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                         const std::vector<double>& weights);

// The rotation alone: R maximising sum w (q - mu_q)^T R (x - mu_x), with the
// same guard; scale fixed to `scale`, t = mu_q - s R mu_x (the paper's
// p' = R (p - c_P) + c_Q when scale is 1, equal weights).
Similarity FitRigid(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                    const std::vector<double>& weights, double scale);

}  // namespace seamap
