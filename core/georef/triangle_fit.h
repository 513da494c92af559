#pragma once
// The paper's baseline: the three keyframes spanning the largest triangle,
// and the rigid SVD transform through them. Monocular SLAM has no metric
// unit, so the SLAM triangle is first scaled by the ratio of the targets' RMS
// distance from their centroid to its own; without that the baseline fails
// outright and a comparison would measure the missing parameter.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/georef/similarity.h"

namespace seamap {

struct TriangleChoice {
  std::array<int, 3> indices{-1, -1, -1};  // into the points given
  double area = 0;                         // in the points' units squared
};

// Exact: the points projected on their best-fit plane, the convex hull, every
// triple of hull vertices (the largest triangle has its corners on the hull).
// Fewer than 3 points: indices -1.
TriangleChoice LargestTriangle(const std::vector<Eigen::Vector3d>& points);

// Rigid SVD (with the reflection guard) of the scaled SLAM corners onto the targets.
Similarity FitTriangle(const std::array<Eigen::Vector3d, 3>& slam, const std::array<Eigen::Vector3d, 3>& targets);

}  // namespace seamap
