#include "core/trajectory/pair_registration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/trajectory/ground_offsets.h"

namespace seamap {
namespace {

// A seabed of distinct points, each with its own descriptor, seen by two
// frames: each frame's keypoints are the points inside its 1 m footprint,
// as heading-free ground offsets.
struct Scene {
  std::vector<cv::Point2d> points;
  cv::Mat descriptors;
  explicit Scene(int n, uint32_t seed) : descriptors(n, 128, CV_8U) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> at(-3, 3);
    for (int k = 0; k < n; ++k) points.push_back({at(rng), at(rng)});
    cv::randu(descriptors, 0, 256);
  }
  // The frame at `position` with `heading`; `noise_m` jitters the offsets.
  std::pair<FrameFeatures, RegistrationFrame> Frame(cv::Point2d position, double heading_rad, double noise_m,
                                                    uint32_t seed) const {
    std::mt19937 rng(seed);
    std::normal_distribution<double> jitter(0, noise_m);
    FrameFeatures f;
    RegistrationFrame r;
    std::vector<int> seen;
    for (int k = 0; k < static_cast<int>(points.size()); ++k) {
      const cv::Point2d a = RotateClockwise(points[k] - position, -heading_rad);  // G = t + Rot(psi) a
      if (std::fabs(a.x) > 0.5 || std::fabs(a.y) > 0.4) continue;
      r.offsets.push_back(a + cv::Point2d(jitter(rng), jitter(rng)));
      f.ideal_px.emplace_back(static_cast<float>(a.x / 0.003), static_cast<float>(a.y / 0.003));  // 3 mm pixels
      seen.push_back(k);
    }
    f.descriptors = cv::Mat(static_cast<int>(seen.size()), 128, CV_8U);
    for (size_t k = 0; k < seen.size(); ++k) descriptors.row(seen[k]).copyTo(f.descriptors.row(static_cast<int>(k)));
    r.position_m = position;
    r.heading_rad = heading_rad;
    r.ground_px_m = 0.003;
    r.footprint_m2 = 0.8;
    return {std::move(f), std::move(r)};
  }
};

TEST(FitRigid, RecoversAKnownMotion) {
  std::vector<cv::Point2d> p, q;
  const cv::Point2d dt(0.3, -0.2);
  const double dpsi = 0.4;
  for (int k = 0; k < 10; ++k) {
    q.push_back({std::cos(k) * 0.5, std::sin(2 * k) * 0.4});
    p.push_back(dt + RotateClockwise(q.back(), dpsi));
  }
  const Rigid2D r = FitRigid(p, q);
  EXPECT_NEAR(r.dt.x, dt.x, 1e-12);
  EXPECT_NEAR(r.dt.y, dt.y, 1e-12);
  EXPECT_NEAR(r.dpsi, dpsi, 1e-12);
}

TEST(RegisterPair, RecoversTheMotionBetweenTwoFramesWhateverTheNavigationsDrift) {
  const Scene scene(6000, 1);
  // The true poses: frame j 0.4 m east of i on the next line, turned 180 deg plus a little.
  const cv::Point2d ti(0.1, 0.2), tj(0.5, 0.35);
  const double psi_i = 0.05, psi_j = M_PI - 0.03;
  auto [fi, ri] = scene.Frame(ti, psi_i, 0.0005, 2);
  auto [fj, rj] = scene.Frame(tj, psi_j, 0.0005, 3);
  ri.features = &fi;
  rj.features = &fj;
  const cv::Point2d dt = RotateClockwise(tj - ti, -psi_i);
  const double dpsi = WrapAngle(psi_j - psi_i);
  for (const double drift : {0.0, 0.8}) {  // the navigation puts j 0.8 m off: the unguided pass finds it
    RegistrationFrame rj_nav = rj;
    rj_nav.position_m = tj + cv::Point2d(drift, -drift / 2);
    RelativeNavNoise noise;
    noise.position_m = drift > 0 ? 0.5 : 0.005;
    noise.heading_rad = 0.01;
    const PairRegistration g = RegisterPair(ri, rj_nav, noise, RegistrationOptions{}, 7);
    ASSERT_TRUE(g.accepted) << g.reason << " (drift " << drift << ")";
    EXPECT_NEAR(g.dt_east_m, dt.x, 0.0005) << drift;
    EXPECT_NEAR(g.dt_north_m, dt.y, 0.0005) << drift;
    EXPECT_NEAR(g.dheading_rad, dpsi, 0.002) << drift;
    EXPECT_GT(g.inliers, 50);
    EXPECT_LT(g.rms_m, 0.002);
    // The covariance is small but not zero, and symmetric.
    EXPECT_GT(g.covariance(0, 0), 0);
    EXPECT_LT(std::sqrt(g.covariance(0, 0)), 0.001);
    EXPECT_NEAR(g.covariance(0, 2), g.covariance(2, 0), 1e-15);
  }
}

TEST(RegisterPair, RefusesFramesThatDoNotOverlapOrDisagreeWithTheNavigation) {
  const Scene scene(6000, 4);
  auto [fi, ri] = scene.Frame({0, 0}, 0, 0.0005, 5);
  auto [fk, rk] = scene.Frame({2.0, 0}, 0, 0.0005, 6);  // no overlap
  ri.features = &fi;
  rk.features = &fk;
  RelativeNavNoise loose;
  loose.position_m = 1.0;
  EXPECT_FALSE(RegisterPair(ri, rk, loose, RegistrationOptions{}, 1).accepted);
  // Overlapping, but the navigation says 0.3 m elsewhere with a 5 mm sigma: refused as disagreeing.
  auto [fj, rj] = scene.Frame({0.3, 0.1}, 0.02, 0.0005, 7);
  rj.features = &fj;
  rj.position_m = {0.6, 0.1};
  RelativeNavNoise tight;
  tight.position_m = 0.005;
  loose.position_m = 0.5;
  EXPECT_TRUE(RegisterPair(ri, rj, loose, RegistrationOptions{}, 2).accepted);
  const PairRegistration g = RegisterPair(ri, rj, tight, RegistrationOptions{}, 2);
  EXPECT_FALSE(g.accepted);
}

}  // namespace
}  // namespace seamap
