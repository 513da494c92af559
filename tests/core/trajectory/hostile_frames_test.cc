// Issue 33, rows 11 and 13: photos that cannot measure motion (uniform
// frames, the same photo twice from a frozen camera) are refused by the
// shared checks and by pair registration, and the navigation filter restarts
// across a gap in time instead of predicting across it step by step.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/camera/frame_projector.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/pair_registration.h"
#include "core/trajectory/seabed_terrain.h"
#include "core/trajectory/trajectory_estimator.h"
#include "core/trajectory/velocity_filter.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(WhyNoTexture, UniformFramesHaveNoneTexturedFramesPass) {
  const auto black = WhyNoTexture(cv::Mat(480, 640, CV_8U, cv::Scalar(0)));
  ASSERT_TRUE(black.has_value());
  EXPECT_EQ(black->rfind("no texture", 0), 0u) << *black;
  EXPECT_TRUE(WhyNoTexture(cv::Mat(480, 640, CV_16UC3, cv::Scalar(40000, 40000, 40000))).has_value());
  EXPECT_TRUE(WhyNoTexture(cv::Mat()).has_value());
  cv::Mat seabed(480, 640, CV_8U);
  cv::randu(seabed, 0, 256);
  EXPECT_FALSE(WhyNoTexture(seabed).has_value());
}

// Keypoints on a grid with random descriptors, their ground offsets at 3 mm a pixel.
std::pair<FrameFeatures, RegistrationFrame> GridFrame(uint32_t seed) {
  FrameFeatures f;
  RegistrationFrame r;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 25; ++x) {
      f.ideal_px.emplace_back(10.f + 25 * x, 10.f + 22 * y);
      r.offsets.emplace_back((f.ideal_px.back().x - 320) * 0.003, (240 - f.ideal_px.back().y) * 0.003);
    }
  f.descriptors = cv::Mat(static_cast<int>(f.ideal_px.size()), 128, CV_8U);
  cv::RNG rng(seed);
  rng.fill(f.descriptors, cv::RNG::UNIFORM, 0, 256);
  r.ground_px_m = 0.003;
  r.footprint_m2 = 1.92 * 1.44;
  return {f, r};
}

TEST(RegisterPair, TheSamePhotoTwiceIsRefusedAsAFrozenCamera) {
  auto [fi, ri] = GridFrame(1);
  FrameFeatures fj = fi;
  RegistrationFrame rj = ri;
  ri.features = &fi;
  rj.features = &fj;
  rj.position_m = {0, 0.1};  // the navigation moved 10 cm, the photo did not
  RelativeNavNoise noise;
  noise.position_m = 0.07;
  const PairRegistration same = RegisterPair(ri, rj, noise, RegistrationOptions{}, 3);
  EXPECT_FALSE(same.accepted);
  EXPECT_EQ(same.reason.rfind("identical frames", 0), 0u) << same.reason;

  // Not bit for bit the same (one keypoint a thousandth of a pixel off), still no parallax.
  fj.ideal_px[7].x += 0.001f;
  const PairRegistration still = RegisterPair(ri, rj, noise, RegistrationOptions{}, 3);
  EXPECT_FALSE(still.accepted);
  EXPECT_EQ(still.reason.rfind("no parallax", 0), 0u) << still.reason;

  // The same photos where the navigation stood still too: a vehicle holding station.
  rj.position_m = {0, 0.01};
  EXPECT_TRUE(RegisterPair(ri, rj, noise, RegistrationOptions{}, 3).accepted);
}

TEST(VelocityFilter, RefusesToPredictAcrossMoreThanADay) {
  VelocityFilter filter{VelocityFilterOptions{}};
  filter.Start(0, 0, 0, 10, 0.05);
  const AttitudeAt level = [](double) { return Attitude{}; };
  try {
    filter.PredictTo(1e8, level);
    ADD_FAILURE() << "predicted 1e8 s ahead";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "time_s") << e.what();
  }
  EXPECT_NO_THROW(filter.PredictTo(3600, level));
}

TEST(TrajectoryEstimator, RestartsAtTheNavigationAcrossAGapAndSaysSo) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 640, 480);
  for (const EstimatorMode mode : {EstimatorMode::kVo, EstimatorMode::kEkf}) {
    EstimatorOptions options;
    options.mode = mode;
    TrajectoryEstimator estimator(camera, options);
    VehiclePose nav;
    nav.altitude_m = 2;
    nav.depth_m = 30;
    for (int k = 0; k < 10; ++k) {
      nav.north_m = 0.1 * k;
      estimator.Add(nullptr, 0.2 * k, nav);
      EXPECT_EQ(estimator.last_flags(), "");
    }
    // A year later (a clock reset): one step, not 1.6e8.
    const double year_s = 365.25 * 86400;
    nav.north_m = 50;
    nav.east_m = -20;
    const VehiclePose placed = estimator.Add(nullptr, year_s, nav);
    EXPECT_EQ(estimator.last_flags(), "restart_after_gap");
    ASSERT_EQ(estimator.gaps().size(), 1u);
    EXPECT_DOUBLE_EQ(estimator.gaps()[0].first, year_s);
    EXPECT_NEAR(estimator.gaps()[0].second, year_s - 1.8, 1e-6);
    EXPECT_DOUBLE_EQ(placed.north_m, 50);
    EXPECT_DOUBLE_EQ(placed.east_m, -20);
    nav.north_m = 50.1;
    estimator.Add(nullptr, year_s + 0.2, nav);
    EXPECT_EQ(estimator.last_flags(), "");
    EXPECT_EQ(estimator.filter_counts().depth_accepted + estimator.filter_counts().depth_rejected, 12)
        << "the counts go on across the restart";
  }
  EstimatorOptions bad;
  bad.max_gap_s = 0;
  try {
    bad.Check();
    ADD_FAILURE() << "max_gap_s 0 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "max_gap_s");
  }
}

// Row 9: the seabed estimate (build --terrain) reads photos with the build's limit too.
TEST(EstimateSeabedTerrain, ReadsPhotosWithTheBuildsImageLimit) {
  testing::TempDir dir;
  const std::string path = (dir / "big.png").string();
  ASSERT_TRUE(cv::imwrite(path, cv::Mat(1500, 2000, CV_8U, cv::Scalar(0))));
  FrameSpec frame;
  frame.image = "big.png";
  frame.image_path = path;
  frame.pose.altitude_m = 2;
  TerrainOptions options;
  options.max_image_pixels = 1'000'000;
  TerrainReport report;
  EXPECT_TRUE(
      EstimateSeabedTerrain({frame, frame}, CameraFromFocalLength(8, 12.9, 640, 480), options, &report).empty());
  ASSERT_FALSE(report.problems.empty());
  EXPECT_NE(
      report.problems[0].find("big.png: image too large: its header says 2000x1500 pixels, over the limit of 1000000"),
      std::string::npos)
      << report.problems[0];
}

}  // namespace
}  // namespace seamap
