#include "core/georef/similarity.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace seamap {
namespace {

Eigen::Matrix3d RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

std::vector<Eigen::Vector3d> RandomPoints(std::mt19937_64& rng, int n, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n; ++i) points.push_back({u(rng), u(rng), u(rng)});
  return points;
}

TEST(FitSimilarity, RecoversRandomSimilaritiesExactly) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> log_scale(std::log(0.01), std::log(100.0)), w(0.1, 5);
  for (int trial = 0; trial < 50; ++trial) {
    Similarity truth;
    truth.scale = std::exp(log_scale(rng));
    truth.rotation = RandomRotation(rng);
    truth.translation = {w(rng) * 100, -w(rng) * 50, w(rng)};
    const auto from = RandomPoints(rng, 20, 10);
    std::vector<Eigen::Vector3d> to;
    std::vector<double> weights;
    for (const auto& p : from) to.push_back(truth.Apply(p)), weights.push_back(w(rng));
    const Similarity fit = FitSimilarity(from, to, weights);
    EXPECT_NEAR(fit.scale / truth.scale, 1.0, 1e-9);
    EXPECT_LT((fit.rotation - truth.rotation).norm(), 1e-9);
    EXPECT_LT((fit.translation - truth.translation).norm(), 1e-9 * (1 + truth.translation.norm()));
  }
}

TEST(FitSimilarity, EqualWeightsMatchEigenUmeyama) {
  std::mt19937_64 rng(3);
  const auto from = RandomPoints(rng, 30, 5);
  std::vector<Eigen::Vector3d> to;
  std::normal_distribution<double> noise(0, 0.3);
  const Eigen::Matrix3d r = RandomRotation(rng);
  for (const auto& p : from)
    to.push_back(2.5 * r * p + Eigen::Vector3d(1, 2, 3) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  Eigen::Matrix3Xd src(3, from.size()), dst(3, to.size());
  for (size_t i = 0; i < from.size(); ++i) src.col(i) = from[i], dst.col(i) = to[i];
  const Eigen::Matrix4d oracle = Eigen::umeyama(src, dst, true);
  const Similarity fit = FitSimilarity(from, to, std::vector<double>(from.size(), 1.0));
  Eigen::Matrix4d ours = Eigen::Matrix4d::Identity();
  ours.topLeftCorner<3, 3>() = fit.scale * fit.rotation;
  ours.topRightCorner<3, 1>() = fit.translation;
  EXPECT_LT((ours - oracle).norm(), 1e-9);
}

TEST(FitSimilarity, AZeroWeightEqualsRemovingThePoint) {
  std::mt19937_64 rng(5);
  auto from = RandomPoints(rng, 12, 5);
  std::vector<Eigen::Vector3d> to;
  std::normal_distribution<double> noise(0, 0.5);
  for (const auto& p : from) to.push_back(0.3 * p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  to[4] += Eigen::Vector3d(50, -20, 10);  // a wild one
  std::vector<double> weights(from.size(), 1.0);
  weights[4] = 0;
  const Similarity with_zero = FitSimilarity(from, to, weights);
  from.erase(from.begin() + 4);
  to.erase(to.begin() + 4);
  const Similarity without = FitSimilarity(from, to, std::vector<double>(from.size(), 1.0));
  EXPECT_NEAR(with_zero.scale, without.scale, 1e-12);
  EXPECT_LT((with_zero.rotation - without.rotation).norm(), 1e-12);
  EXPECT_LT((with_zero.translation - without.translation).norm(), 1e-12);
}

TEST(FitSimilarity, CoplanarPointsNeverGiveAMirror) {
  // Points on a plane: C is singular, det(C) says nothing; a naive U V^T may
  // reflect through the plane. The guard must return the proper rotation.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<Eigen::Vector3d> from, to;
    const Eigen::Matrix3d r = RandomRotation(rng);
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d p(u(rng), u(rng), 0);
      from.push_back(p);
      to.push_back(0.7 * r * p + Eigen::Vector3d(3, 4, 5));
    }
    const Similarity fit = FitSimilarity(from, to, std::vector<double>(from.size(), 1.0));
    EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-9);
    for (size_t i = 0; i < from.size(); ++i) EXPECT_LT((fit.Apply(from[i]) - to[i]).norm(), 1e-9);
  }
}

TEST(FitSimilarity, MirroredTargetsGiveTheBestProperRotation) {
  // Targets that are a true mirror image: no rotation fits; the answer must
  // still be a rotation (det +1), never the reflection.
  std::vector<Eigen::Vector3d> from = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}}, to;
  for (const auto& p : from) to.push_back({p.x(), p.y(), -p.z()});
  const Similarity fit = FitSimilarity(from, to, {1, 1, 1, 1});
  EXPECT_NEAR(fit.rotation.determinant(), 1.0, 1e-12);
}

TEST(FitRigid, KeepsTheScaleItIsGiven) {
  std::vector<Eigen::Vector3d> from = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, to;
  Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (const auto& p : from) to.push_back(4.0 * r * p + Eigen::Vector3d(10, 0, 0));
  const Similarity fit = FitRigid(from, to, {1, 1, 1}, 4.0);
  EXPECT_DOUBLE_EQ(fit.scale, 4.0);
  EXPECT_LT((fit.rotation - r).norm(), 1e-12);
  EXPECT_LT((fit.Apply(from[2]) - to[2]).norm(), 1e-12);
}

TEST(FitSimilarity, RefusesBadInput) {
  EXPECT_THROW(FitSimilarity({}, {}, {}), std::invalid_argument);
  EXPECT_THROW(FitSimilarity({{1, 1, 1}, {1, 1, 1}}, {{0, 0, 0}, {1, 0, 0}}, {1, 1}), std::invalid_argument);
  EXPECT_THROW(FitSimilarity({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}, {0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace seamap
