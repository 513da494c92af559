#include "core/stereo/icp_baseline.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

TEST(IcpBaseline, RecoversAKnownPoseInTheRightDirection) {
  // A bumpy 3 x 2 m surface with a box on it, in the object frame; the camera 3.5 m above, turned 20 deg.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> model;
  for (int k = 0; k < 1500; ++k) {
    const double x = 1.5 * u(rng), y = u(rng);
    double z = 3.5 + 0.05 * std::sin(3 * x) * std::cos(2 * y);
    if (std::abs(x - 0.3) < 0.4 && std::abs(y + 0.2) < 0.3) z -= 0.5;  // the box's top, nearer the camera
    model.emplace_back(x, y, z);
  }
  Eigen::Matrix<double, 6, 1> v;
  v << 0.02, -0.01, 0.35, 0.12, -0.08, 0.03;
  const Rigid object_from_camera = RigidFromVector(v);
  std::vector<Eigen::Vector3d> scene;  // the same surface seen from the camera, every second point
  for (size_t k = 0; k < model.size(); k += 2) scene.push_back(object_from_camera.inverse() * model[k]);
  const IcpRegistration reg = RegisterIcp(model, scene, IcpOptions{});
  const Rigid error = reg.object_from_camera.inverse() * object_from_camera;
  EXPECT_LT(error.translation().norm(), 0.005) << reg.object_from_camera.matrix();
  EXPECT_LT(RotationAngleDeg(error.linear()), 0.2);
  EXPECT_LT(reg.rms_m, 0.005);
  EXPECT_GT(reg.near, 600);
}

}  // namespace
}  // namespace seamap
