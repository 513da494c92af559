#include "core/georef/seabed_altitude.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

TEST(AltitudeFromCloud, MedianSeabedBelowEachKeyframe) {
  // A seabed sloping 1:10 east at about 20 m depth, with a few stray points above it.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50, 50);
  std::vector<Eigen::Vector3d> cloud;
  for (int i = 0; i < 20000; ++i) {
    const double e = u(rng), n = u(rng);
    cloud.push_back({e, n, -20 + 0.1 * e});
  }
  for (int i = 0; i < 200; ++i) cloud.push_back({u(rng), u(rng), -12.0});  // fish: 1 % above the seabed
  const std::vector<Eigen::Vector3d> keyframes = {{0, 0, -12.5}, {30, -10, -12.5}, {200, 0, -12.5}};
  const auto altitude = AltitudeFromCloud(keyframes, cloud, {});
  ASSERT_EQ(altitude.size(), 3u);
  ASSERT_TRUE(altitude[0].has_value());
  EXPECT_NEAR(*altitude[0], 7.5, 0.05);
  ASSERT_TRUE(altitude[1].has_value());
  EXPECT_NEAR(*altitude[1], 4.5, 0.05);   // seabed at -17 m there
  EXPECT_FALSE(altitude[2].has_value());  // off the cloud
}

TEST(AltitudeFromCloud, NoneWhereTheSeabedIsNotBelowOrTooSparse) {
  const std::vector<Eigen::Vector3d> cloud = {{0, 0, -5}, {0.5, 0, -5}, {0, 0.5, -5}, {0.5, 0.5, -5}, {1, 1, -5}};
  const auto altitude = AltitudeFromCloud({{0, 0, -10}, {0, 0, -1}}, cloud, {});
  EXPECT_FALSE(altitude[0].has_value());  // "seabed" above the vehicle
  ASSERT_TRUE(altitude[1].has_value());
  EXPECT_NEAR(*altitude[1], 4, 1e-12);
  SeabedAltitudeOptions strict;
  strict.min_points = 6;
  EXPECT_FALSE(AltitudeFromCloud({{0, 0, -1}}, cloud, strict)[0].has_value());
}

}  // namespace
}  // namespace seamap
