#include "core/stereo/stereo_bundle.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

// Poses as rotation vector (rad) and translation (m).
using V6 = Eigen::Matrix<double, 6, 1>;

// Pair 0 sees 5 points, pair 1 sees 400: alone, pair 0's pose is poor; held
// to the rig's measured motion from pair 1 it inherits pair 1's precision.
TEST(StereoBundle, TheRigsMotionCarriesOnePairsPrecisionToAnother) {
  RectifiedRig rig;  // the paper's: f 1040 px, 0.25 m baseline, 1200 x 900
  rig.f = 1040, rig.cx = 600, rig.cy = 450, rig.baseline_m = 0.25;
  const Rigid truth0 = RigidFromVector((V6() << M_PI, 0.05, 0.1, 0.2, -0.1, 3.6).finished()),
              truth1 = truth0 * RigidFromVector((V6() << 0.02, -0.03, 0.1, 0.5, 0.2, 0.05).finished());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::normal_distribution<double> pixel_noise(0, 0.3);
  const auto solve = [&](bool with_motion) {
    BundleProblem problem;
    problem.poses = {truth0 * RigidFromVector((V6() << 0.01, -0.01, 0.02, 0.03, -0.02, 0.02).finished()),
                     truth1 * RigidFromVector((V6() << 0.004, 0, 0, 0, 0.01, 0).finished())};
    problem.pose_fixed = {false, false};
    problem.sigma_px = 0.3;
    for (int k = 0; k < 405; ++k) {
      BundlePoint p;
      p.xyz = p.prior_xyz = Eigen::Vector3d(u(rng), u(rng), 0.2 * u(rng));
      p.prior_cov = Eigen::Matrix3d::Identity() * 1e-8;  // a well-known model
      p.has_prior = true;
      problem.points.push_back(p);
      BundleObservation o;
      o.pose = k < 5 ? 0 : 1;
      o.point = k;
      if (!ProjectToPair(rig, o.pose == 0 ? truth0 : truth1, p.xyz, &o.left_px, &o.right_px)) continue;
      o.left_px += cv::Point2d(pixel_noise(rng), pixel_noise(rng));
      o.right_px += cv::Point2d(pixel_noise(rng), pixel_noise(rng));
      problem.observations.push_back(o);
    }
    if (with_motion) {
      BundleMotion m;
      m.from_pose = 0, m.to_pose = 1;
      m.from_camera_from_to_camera = truth0.inverse() * truth1;
      m.sigma_m = 1e-4, m.sigma_rad = 1e-5;
      problem.motions.push_back(m);
    }
    const BundleResult solved = SolveBundle(&problem, rig, 0);
    EXPECT_TRUE(solved.has_covariance);
    const std::vector<Eigen::Vector3d> object{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0.5}};
    return std::pair{CheckPointError(problem.poses[0], truth0, object),
                     PointSigmaM(problem.poses[0], solved.covariance, object)};
  };
  const auto [alone_m, alone_sigma_m] = solve(false);
  const auto [held_m, held_sigma_m] = solve(true);
  EXPECT_LT(held_m, 0.5 * alone_m) << alone_m << " alone";
  EXPECT_LT(held_sigma_m, 0.5 * alone_sigma_m);
  EXPECT_LT(held_m, 4 * held_sigma_m + 1e-5);
}

}  // namespace
}  // namespace seamap
