#include "core/georef/slam_path.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

// A path in SLAM units: 100 s east, a 90 degree turn over 10 s, 100 s north;
// written in tilted, scaled axes to show nothing depends on them.
std::vector<Keyframe> LPath() {
  const Eigen::Matrix3d axes = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0.2, 1, 0.4).normalized()).toRotationMatrix();
  std::vector<Keyframe> k;
  int line = 1;
  auto add = [&](double t, Eigen::Vector3d p) {
    Keyframe f;
    f.time_s = 1000 + t;
    f.position_slam = 0.07 * axes * p;
    f.world_from_cam = Eigen::Quaterniond::Identity();  // unused here; set, so copies read no unset values
    f.line = line++;
    k.push_back(f);
  };
  for (double t = 0; t < 100; t += 0.5) add(t, {0.6 * t, 0, 0});
  const double r = 0.6 * 10 / (M_PI / 2);
  for (double t = 100; t < 110; t += 0.25) {
    const double a = (t - 100) / 10 * M_PI / 2;
    add(t, {60 + r * std::sin(a), r * (1 - std::cos(a)), 0});
  }
  for (double t = 110; t < 210; t += 0.5) add(t, {60 + r, r + 0.6 * (t - 110), 0});
  return k;
}

TEST(SlamPath, FindsTheTurnAndTwoLegs) {
  const SlamPath path(LPath(), {});
  ASSERT_EQ(path.legs().size(), 2u);
  EXPECT_LT(path.legs()[0].end_s, 1000 + 101);
  EXPECT_GT(path.legs()[1].start_s, 1000 + 109);
  // 10 s into the second leg, the time since the turn counts from its end.
  for (size_t i = 0; i < path.size(); ++i)
    if (std::fabs(path.time(i) - 1130) < 1e-9) {
      EXPECT_NEAR(path.SinceTurn(i), 1130 - path.legs()[1].start_s + 0.5, 1.0);
    }
}

TEST(SlamPath, StraightnessAndSteadinessAreScaleFree) {
  const SlamPath path(LPath(), {});
  EXPECT_NEAR(path.Straightness(1010, 1090), 1.0, 1e-9);
  EXPECT_LT(path.Straightness(1080, 1130), 0.95);  // across the corner
  EXPECT_NEAR(path.SpeedVariation(1010, 1090), 0.0, 1e-9);
  EXPECT_NEAR(path.SpeedAt(1050, 5, 0, 1e9), 0.07 * 0.6, 1e-9);
  const Eigen::Vector3d along = path.DirectionAt(1050, 5, 0, 1e9);
  EXPECT_NEAR(along.norm(), 1.0, 1e-12);
}

TEST(SlamPath, ReportsAJumpAndAGapAsSuspectedResets) {
  auto k = LPath();
  for (size_t i = 100; i < k.size(); ++i) k[i].position_slam += Eigen::Vector3d(5, 0, 0);  // a jump of ~170 steps
  for (size_t i = 300; i < k.size(); ++i) k[i].time_s += 60;                               // a minute lost
  const auto resets = SlamPath(k, {}).SuspectedResets();
  ASSERT_EQ(resets.size(), 2u);
  EXPECT_EQ(resets[0].line, k[100].line);
  EXPECT_NE(resets[0].why.find("jump"), std::string::npos);
  EXPECT_EQ(resets[1].line, k[300].line);
  EXPECT_NE(resets[1].why.find("gap"), std::string::npos);
}

}  // namespace
}  // namespace seamap
