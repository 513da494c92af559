#include "core/georef/triangle_fit.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace seamap {
namespace {

TEST(LargestTriangle, FindsTheCornersOfATiltedRectangle) {
  // A 10 x 4 rectangle with interior points, tilted out of every axis plane:
  // the largest triangle is half the rectangle, 20, with three of its corners.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0.3).normalized()).toRotationMatrix();
  std::vector<Eigen::Vector3d> points;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 200; ++i) points.push_back(tilt * Eigen::Vector3d(1 + 8 * u(rng), 0.5 + 3 * u(rng), 0));
  for (const auto& c :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 0, 0), Eigen::Vector3d(10, 4, 0), Eigen::Vector3d(0, 4, 0)})
    points.push_back(tilt * c);
  const TriangleChoice best = LargestTriangle(points);
  EXPECT_NEAR(best.area, 20.0, 1e-9);
  for (int index : best.indices) EXPECT_GE(index, 200);
}

TEST(LargestTriangle, TooFewPoints) {
  EXPECT_EQ(LargestTriangle({{0, 0, 0}, {1, 0, 0}}).indices[0], -1);
}

TEST(FitTriangle, RecoversScaleRotationTranslationWithoutAMirror) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g(0, 1);
  for (int trial = 0; trial < 30; ++trial) {
    const Eigen::Matrix3d r = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    const double scale = std::exp(g(rng) * 2);
    const Eigen::Vector3d t(g(rng) * 100, g(rng) * 100, g(rng));
    std::array<Eigen::Vector3d, 3> slam, targets;
    for (int k = 0; k < 3; ++k) {
      slam[k] = {g(rng), g(rng), g(rng)};
      targets[k] = scale * r * slam[k] + t;
    }
    const Similarity fit = FitTriangle(slam, targets);
    EXPECT_NEAR(fit.scale / scale, 1, 1e-9);
    EXPECT_NEAR(fit.rotation.determinant(), 1, 1e-9);  // three points are coplanar: the guard matters
    EXPECT_LT((fit.rotation - r).norm(), 1e-8);
    for (int k = 0; k < 3; ++k) EXPECT_LT((fit.Apply(slam[k]) - targets[k]).norm(), 1e-8 * (1 + t.norm()));
  }
}

}  // namespace
}  // namespace seamap
