#include "core/stereo/rigid_transform.h"

#include <gtest/gtest.h>

#include <random>

#include "core/util/error.h"

namespace seamap {
namespace {

Rigid Pose(double rx, double ry, double rz, double tx, double ty, double tz) {
  Eigen::Matrix<double, 6, 1> v;
  v << rx, ry, rz, tx, ty, tz;
  return RigidFromVector(v);
}

TEST(RigidTransform, FitRecoversARigidTransformWithoutScale) {
  const Rigid dst_from_src = Pose(0.3, -0.2, 1.1, 0.5, -2, 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Eigen::Vector3d> src, dst, dst_scaled;
  for (int k = 0; k < 20; ++k) {
    src.emplace_back(u(rng), u(rng), u(rng) + 5);
    dst.push_back(dst_from_src * src.back());
    dst_scaled.push_back(1.1 * dst.back());
  }
  const Rigid fit = FitRigid(src, dst);
  EXPECT_LT((fit.matrix() - dst_from_src.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  // A 10 % scaled target must not be absorbed as scale (Umeyama's default would).
  const Rigid scaled = FitRigid(src, dst_scaled);
  EXPECT_NEAR(scaled.linear().determinant(), 1, 1e-9);
  EXPECT_NEAR((scaled.linear().transpose() * scaled.linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-9);
}

TEST(RigidTransform, JsonRoundTripAndBadMatrices) {
  const Rigid t = Pose(0.1, 0.2, 0.3, 1, 2, 3);
  const Rigid back = RigidFromJson(RigidToJson(t), "x.json", "pose");
  EXPECT_LT((back.matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  nlohmann::json bad = RigidToJson(t);
  bad[0][0] = 2.0;
  EXPECT_THROW(RigidFromJson(bad, "x.json", "pose"), InputError);
  EXPECT_THROW(RigidFromJson(nlohmann::json::array({1, 2}), "x.json", "pose"), InputError);
}

TEST(RigidTransform, CheckPointErrorIsZeroForEqualPosesAndTheOffsetForAShift) {
  const Rigid truth = Pose(0.1, -0.4, 2, 0.3, 0.2, 6);
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1, 0, 2}, {-1, 1, 1}};
  EXPECT_NEAR(CheckPointError(truth, truth, points), 0, 1e-12);
  Rigid shifted = truth;
  shifted.translation() += Eigen::Vector3d(0.003, -0.004, 0);  // 5 mm
  EXPECT_NEAR(CheckPointError(shifted, truth, points), 0.005, 1e-9);
}

TEST(RigidTransform, PointSigmaPredictsHowFarThePointsMove) {
  const Rigid object_from_camera = Pose(0.2, -0.3, 1.1, 0.4, -0.2, -3.6);
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {1.2, 0, 0.3}, {-0.8, 1, -0.5}, {0.3, -1.5, 0.2}};
  // Translation alone: every point moves as the camera does, sqrt(3) sigma.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * 1e-6;  // 1 mm per axis
  EXPECT_NEAR(PointSigmaM(object_from_camera, covariance, points), std::sqrt(3.0) * 1e-3, 1e-7);

  // With rotation and correlations: the RMS displacement of poses drawn from the covariance.
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Random() * 1e-3;
  covariance = a * a.transpose();
  const double predicted = PointSigmaM(object_from_camera, covariance, points);
  const Eigen::Matrix<double, 6, 6> root = covariance.llt().matrixL();
  std::mt19937 rng(4);
  std::normal_distribution<double> gauss;
  const Eigen::Matrix<double, 6, 1> v = RigidToVector(object_from_camera);
  double sum = 0;
  const int draws = 20000;
  for (int k = 0; k < draws; ++k) {
    Eigen::Matrix<double, 6, 1> z;
    for (int i = 0; i < 6; ++i) z[i] = gauss(rng);
    const Rigid drawn = RigidFromVector(v + root * z);
    for (const Eigen::Vector3d& p : points)
      sum += (drawn.inverse() * p - object_from_camera.inverse() * p).squaredNorm() / points.size();
  }
  EXPECT_NEAR(predicted, std::sqrt(sum / draws), 0.03 * predicted);
  EXPECT_EQ(PointSigmaM(object_from_camera, covariance, {}), 0);
}

}  // namespace
}  // namespace seamap
