#include "core/controllers/pose_source.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const CameraModel kCamera = CameraFromFocalLength(8, 12.9, 160, 120);

FrameSpec Frame(const std::string& path, double east_m) {
  FrameSpec f;
  f.image_path = path;
  f.image = "f.png";
  f.time_s = 1.0;
  f.pose.east_m = east_m;
  f.pose.altitude_m = 2;
  return f;
}

TEST(PoseSourceTest, NavigationLeavesEveryPoseAsGiven) {
  PoseSource poses(kCamera, {});
  EXPECT_EQ(poses.name(), "nav");
  std::vector<FrameSpec> frames{Frame("a", 1), Frame("b", 2)};
  std::vector<std::string> flags;
  EXPECT_TRUE(poses.PlaceSurvey(&frames, &flags).is_null());
  EXPECT_EQ(flags, (std::vector<std::string>{"", ""}));
  EXPECT_EQ(frames[1].pose.east_m, 2);
  EXPECT_FALSE(frames[1].nav_pose);
  EXPECT_TRUE(poses.Place(&frames[0]).empty());  // nothing decoded
  EXPECT_FALSE(frames[0].nav_pose);
}

TEST(PoseSourceTest, FilterHandsBackThePhotoItDecodedAndKeepsTheNavigationPose) {
  testing::TempDir dir;
  const std::string path = (dir / "f.png").string();
  cv::Mat photo(120, 160, CV_8UC1);
  cv::randu(photo, 0, 255);
  ASSERT_TRUE(cv::imwrite(path, photo));
  PoseSourceOptions options;
  options.mode = PoseMode::kFilter;
  options.filter = EstimatorOptionsFrom("ekf", RefineOptions{}, "--nav-mode");
  PoseSource poses(kCamera, options);
  EXPECT_EQ(poses.name(), "ekf");
  FrameSpec f = Frame(path, 3);
  const cv::Mat decoded = poses.Place(&f);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(cv::norm(decoded, photo, cv::NORM_INF), 0);
  ASSERT_TRUE(f.nav_pose);
  EXPECT_EQ(f.nav_pose->east_m, 3);

  FrameSpec missing = Frame((dir / "none.png").string(), 4);
  EXPECT_TRUE(poses.Place(&missing).empty());  // placed by the filter's prediction
  EXPECT_TRUE(missing.nav_pose);
}

TEST(PoseSourceTest, FilterNeedsTheFramesTimes) {
  PoseSourceOptions options;
  options.mode = PoseMode::kFilter;
  options.filter = EstimatorOptionsFrom("vo", RefineOptions{}, "--nav-mode");
  PoseSource poses(kCamera, options);
  EXPECT_EQ(poses.name(), "vo");
  FrameSpec f = Frame("f.png", 0);
  f.time_s.reset();
  try {
    poses.Place(&f);
    FAIL() << "a frame without a time was placed";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "time_s");
  }
  std::vector<FrameSpec> frames{f};
  EXPECT_THROW(poses.PlaceSurvey(&frames), InputError);
}

TEST(PoseSourceTest, EstimatorOptionsNameTheOptionOfABadMode) {
  try {
    EstimatorOptionsFrom("kalman", RefineOptions{}, "--nav-mode");
    FAIL() << "an unknown mode was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--nav-mode");
  }
  RefineOptions exact;
  exact.nav_noise_m = 0;
  EXPECT_GT(EstimatorOptionsFrom("ekf", exact, "--mode").nav_sigma_m, 0);  // floored
}

}  // namespace
}  // namespace seamap
