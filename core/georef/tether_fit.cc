#include "core/georef/tether_fit.h"

#include <cmath>

namespace seamap {

Similarity FitThroughTether(const Similarity& start, const std::vector<Eigen::Vector3d>& slam,
                            const std::vector<Eigen::Vector3d>& offsets_enu_m,
                            const std::vector<Eigen::Vector3d>& buoy_enu_m, const std::vector<double>& weights) {
  const size_t n = slam.size();
  std::vector<Eigen::Vector3d> offsets(n);  // metres, SLAM axes
  for (size_t i = 0; i < n; ++i) offsets[i] = start.rotation.transpose() * offsets_enu_m[i];
  Similarity fit = start;
  std::vector<Eigen::Vector3d> p(n), a(n), c(n);
  for (int round = 0; round < 50; ++round) {
    const Similarity before = fit;
    // Rotation and translation for this scale (Kabsch with the reflection guard).
    for (size_t i = 0; i < n; ++i) p[i] = fit.scale * slam[i] - offsets[i];
    const Similarity rigid = FitRigid(p, buoy_enu_m, weights, 1.0);
    fit.rotation = rigid.rotation;
    // Scale and translation for this rotation: q + R o = s R x + t, linear.
    double total = 0;
    Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_c = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      a[i] = fit.rotation * slam[i];
      c[i] = buoy_enu_m[i] + fit.rotation * offsets[i];
      total += weights[i];
      mean_a += weights[i] * a[i];
      mean_c += weights[i] * c[i];
    }
    mean_a /= total;
    mean_c /= total;
    double num = 0, den = 0;
    for (size_t i = 0; i < n; ++i) {
      num += weights[i] * (a[i] - mean_a).dot(c[i] - mean_c);
      den += weights[i] * (a[i] - mean_a).squaredNorm();
    }
    if (!(den > 0)) return start;
    fit.scale = num / den;
    fit.translation = mean_c - fit.scale * mean_a;
    const double change = std::fabs(fit.scale / before.scale - 1) + (fit.rotation - before.rotation).norm();
    if (change < 1e-12) break;
  }
  return fit.scale > 0 ? fit : start;
}

}  // namespace seamap
