#include "core/geo/rotation.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace seamap {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The hand-written inverse the trajectory evaluation used before (heading,
// then pitch, then roll undone one after the other).
Eigen::Vector3d OldToBody(const Eigen::Vector3d& ned, double heading_deg, double pitch_deg, double roll_deg) {
  const double psi = heading_deg * kDeg, theta = pitch_deg * kDeg, phi = roll_deg * kDeg;
  const double x1 = std::cos(psi) * ned.x() + std::sin(psi) * ned.y();
  const double y1 = -std::sin(psi) * ned.x() + std::cos(psi) * ned.y();
  const double z1 = ned.z();
  const double x2 = std::cos(theta) * x1 - std::sin(theta) * z1;
  const double z2 = std::sin(theta) * x1 + std::cos(theta) * z1;
  return {x2, std::cos(phi) * y1 + std::sin(phi) * z2, -std::sin(phi) * y1 + std::cos(phi) * z2};
}

TEST(Rotation, NedFromBodyIsTheZyxProductBitForBit) {
  for (double heading : {0.0, 37.5, 90.0, 211.0, 359.9})
    for (double pitch : {-20.0, 0.0, 4.5})
      for (double roll : {-7.0, 0.0, 12.25}) {
        const Eigen::Matrix3d expected = (Eigen::AngleAxisd(heading * kDeg, Eigen::Vector3d::UnitZ()) *
                                          Eigen::AngleAxisd(pitch * kDeg, Eigen::Vector3d::UnitY()) *
                                          Eigen::AngleAxisd(roll * kDeg, Eigen::Vector3d::UnitX()))
                                             .toRotationMatrix();
        EXPECT_EQ(NedFromBodyDeg(heading, pitch, roll), expected);
        EXPECT_EQ(RotationZyx(heading * kDeg, pitch * kDeg, roll * kDeg), expected);
        const Eigen::Vector3d v(1.5, -0.25, 3);
        const Eigen::Vector3d body = expected.transpose() * v;
        EXPECT_LT((body - OldToBody(v, heading, pitch, roll)).cwiseAbs().maxCoeff(), 1e-12);
      }
}

TEST(Rotation, NedFromBodyFollowsTheStatedConvention) {
  // Heading 90: the bow points east.
  EXPECT_TRUE((NedFromBodyDeg(90, 0, 0) * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  // Pitch +10 (bow up): the body's down axis tilts forward (north at heading 0).
  EXPECT_GT((NedFromBodyDeg(0, 10, 0) * Eigen::Vector3d::UnitZ()).x(), 0.17);
  // Roll +10 (starboard down): the down axis tilts to port (west at heading 0).
  EXPECT_LT((NedFromBodyDeg(0, 0, 10) * Eigen::Vector3d::UnitZ()).y(), -0.17);
}

TEST(Rotation, RigMountingsAreExactWithoutAMountRotation) {
  Eigen::Matrix3d down, forward;
  down << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  forward << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  EXPECT_EQ(BodyFromCamera(CameraLooking::kDown), down);
  EXPECT_EQ(BodyFromCamera(CameraLooking::kForward), forward);
}

TEST(Rotation, ForwardIsDownPitchedUpByNinetyDegrees) {
  const Eigen::Matrix3d pitched = BodyFromCamera(CameraLooking::kDown, Eigen::Vector3d(0, 90, 0));
  EXPECT_LT((pitched - BodyFromCamera(CameraLooking::kForward)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Rotation, MountRotationIsAppliedAboutTheBodyAxes) {
  const Eigen::Vector3d rpy(3, -8, 45);
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(rpy.z() * kDeg, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(rpy.y() * kDeg, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(rpy.x() * kDeg, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix() *
                                   BodyFromCamera(CameraLooking::kDown);
  EXPECT_EQ(BodyFromCamera(CameraLooking::kDown, rpy), expected);
}

}  // namespace
}  // namespace seamap
