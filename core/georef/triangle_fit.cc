#include "core/georef/triangle_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace seamap {
namespace {

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; indices of the hull's corners (collinear ones dropped).
std::vector<int> ConvexHull(const std::vector<Eigen::Vector2d>& p) {
  std::vector<int> order(p.size());
  for (size_t i = 0; i < p.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return p[a].x() < p[b].x() || (p[a].x() == p[b].x() && p[a].y() < p[b].y()); });
  if (order.size() < 3) return order;
  std::vector<int> hull(2 * order.size());
  size_t k = 0;
  for (int i : order) {
    while (k >= 2 && Cross(p[hull[k - 2]], p[hull[k - 1]], p[i]) <= 0) --k;
    hull[k++] = i;
  }
  for (size_t j = order.size() - 1, lower = k + 1; j-- > 0;) {
    const int i = order[j];
    while (k >= lower && Cross(p[hull[k - 2]], p[hull[k - 1]], p[i]) <= 0) --k;
    hull[k++] = i;
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace

TriangleChoice LargestTriangle(const std::vector<Eigen::Vector3d>& points) {
  TriangleChoice best;
  if (points.size() < 3) return best;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // ascending: columns 2 and 1 span the plane
  std::vector<Eigen::Vector2d> flat;
  for (const auto& p : points)
    flat.push_back({(p - mean).dot(eig.eigenvectors().col(2)), (p - mean).dot(eig.eigenvectors().col(1))});
  const std::vector<int> hull = ConvexHull(flat);
  for (size_t a = 0; a < hull.size(); ++a)
    for (size_t b = a + 1; b < hull.size(); ++b)
      for (size_t c = b + 1; c < hull.size(); ++c) {
        // The area in 3D, as the paper defines it: 1/2 |(P2 - P1) x (P3 - P1)|.
        const double area = 0.5 * (points[hull[b]] - points[hull[a]]).cross(points[hull[c]] - points[hull[a]]).norm();
        if (area > best.area) best = {{hull[a], hull[b], hull[c]}, area};
      }
  return best;
}

Similarity FitTriangle(const std::array<Eigen::Vector3d, 3>& slam, const std::array<Eigen::Vector3d, 3>& targets) {
  const Eigen::Vector3d cs = (slam[0] + slam[1] + slam[2]) / 3, cq = (targets[0] + targets[1] + targets[2]) / 3;
  double rs = 0, rq = 0;
  for (int k = 0; k < 3; ++k) {
    rs += (slam[k] - cs).squaredNorm();
    rq += (targets[k] - cq).squaredNorm();
  }
  const double scale = rs > 0 ? std::sqrt(rq / rs) : 1.0;
  return FitRigid({slam.begin(), slam.end()}, {targets.begin(), targets.end()}, {1, 1, 1}, scale);
}

}  // namespace seamap
