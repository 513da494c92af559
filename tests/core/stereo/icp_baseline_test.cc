#include "core/stereo/icp_baseline.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

// A bumpy 3 x 2 m seabed 3.5 m below the camera with two boxes standing on it
// (their tops nearer the camera), in the object frame; another layout has
// boxes of other sizes in other places, and none when bare.
enum class Layout { kWellhead, kOther, kBare };
std::vector<Eigen::Vector3d> SeabedWithBoxes(int points, Layout layout, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> cloud;
  for (int k = 0; k < points; ++k) {
    const double x = 1.5 * u(rng), y = u(rng);
    double z = 3.5 + 0.02 * std::sin(3 * x) * std::cos(2 * y);
    if (layout == Layout::kWellhead) {
      if (std::abs(x - 0.3) < 0.4 && std::abs(y + 0.2) < 0.3) z -= 0.5;
      if (std::abs(x + 0.8) < 0.2 && std::abs(y - 0.5) < 0.15) z -= 0.3;
    } else if (layout == Layout::kOther) {
      if (std::abs(x + 0.5) < 0.25 && std::abs(y + 0.4) < 0.25) z -= 0.3;
      if (std::abs(x - 0.9) < 0.08 && std::abs(y - 0.1) < 0.5) z -= 0.5;
    }
    cloud.emplace_back(x, y, z);
  }
  return cloud;
}

Rigid TestPose() {
  Eigen::Matrix<double, 6, 1> v;
  v << 0.02, -0.01, 0.35, 0.12, -0.08, 0.03;
  return RigidFromVector(v);
}

TEST(IcpBaseline, TheSeabedPlaneIsSetApartFromTheStructure) {
  const std::vector<Eigen::Vector3d> cloud = SeabedWithBoxes(3000, Layout::kWellhead, 1);
  int on_boxes = 0;
  for (const Eigen::Vector3d& p : cloud) on_boxes += p.z() < 3.2;
  const std::vector<Eigen::Vector3d> structure = OffDominantPlane(cloud, 0.04, 0.08);
  EXPECT_EQ(static_cast<int>(structure.size()), on_boxes);
  for (const Eigen::Vector3d& p : structure) EXPECT_LT(p.z(), 3.2);

  // No plane holds a third of a cloud filling a cube: nothing is set apart.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> cube;
  for (int k = 0; k < 500; ++k) cube.emplace_back(u(rng), u(rng), u(rng));
  EXPECT_EQ(OffDominantPlane(cube, 0.04, 0.08).size(), cube.size());
}

TEST(IcpBaseline, RecoversAKnownPoseAndCallsItFound) {
  const std::vector<Eigen::Vector3d> model = SeabedWithBoxes(3000, Layout::kWellhead, 2);
  const Rigid object_from_camera = TestPose();
  std::vector<Eigen::Vector3d> scene;  // the same surfaces seen from the camera, other samples
  for (const Eigen::Vector3d& p : SeabedWithBoxes(1500, Layout::kWellhead, 5))
    scene.push_back(object_from_camera.inverse() * p);
  const IcpOptions options;
  const IcpRegistration reg = RegisterIcp(model, scene, options);
  const Rigid error = reg.object_from_camera.inverse() * object_from_camera;
  EXPECT_LT(error.translation().norm(), 0.01) << reg.object_from_camera.matrix();
  EXPECT_LT(RotationAngleDeg(error.linear()), 0.3);
  EXPECT_GT(reg.structure, 100);
  EXPECT_GT(reg.near, 0.6 * reg.structure);
  std::string reason;
  EXPECT_TRUE(IcpFound(reg, options, &reason)) << reason;
}

TEST(IcpBaseline, AnotherLayoutOnTheSameSeabedIsNotFound) {
  // The seabed alone agrees with the model wherever it slides; other boxes must
  // not: before the found rule looked at the structure, such a slide counted as
  // found with most points "near".
  const std::vector<Eigen::Vector3d> model = SeabedWithBoxes(3000, Layout::kWellhead, 2);
  std::vector<Eigen::Vector3d> scene;
  for (const Eigen::Vector3d& p : SeabedWithBoxes(1500, Layout::kOther, 5)) scene.push_back(TestPose().inverse() * p);
  const IcpOptions options;
  const IcpRegistration reg = RegisterIcp(model, scene, options);
  std::string reason;
  EXPECT_FALSE(IcpFound(reg, options, &reason)) << reg.near << " of " << reg.structure;
  EXPECT_NE(reason.find("off the seabed plane"), std::string::npos) << reason;

  // A bare seabed has no structure to pin the pose: not found either.
  std::vector<Eigen::Vector3d> bare;
  for (const Eigen::Vector3d& p : SeabedWithBoxes(1500, Layout::kBare, 6)) bare.push_back(TestPose().inverse() * p);
  EXPECT_FALSE(IcpFound(RegisterIcp(model, bare, options), options, nullptr));
}

}  // namespace
}  // namespace seamap
