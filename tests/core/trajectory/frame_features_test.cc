#include "core/trajectory/frame_features.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/trajectory/ground_offsets.h"

namespace seamap {
namespace {

cv::Mat Texture(int width, int height) {
  cv::Mat m(height, width, CV_8U);
  cv::randu(m, 0, 256);
  cv::GaussianBlur(m, m, {0, 0}, 2.0);
  cv::normalize(m, m, 0, 255, cv::NORM_MINMAX);
  return m;
}

TEST(FrameFeatures, AFrameOfAnotherSizeGivesKeypointsInTheCamerasPixels) {
  // The same scene at full size and at half size: keypoints found in the
  // half-size frame land where the full-size ones are, in full-size ideal pixels.
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 640, 480);
  const cv::Mat full = Texture(640, 480);
  cv::Mat half;
  cv::resize(full, half, {320, 240}, 0, 0, cv::INTER_AREA);
  FeatureOptions options;
  const FrameFeatures a = DetectFeatures(full, camera, options);
  const FrameFeatures b = DetectFeatures(half, camera, options);
  ASSERT_GT(a.ideal_px.size(), 200u);
  ASSERT_GT(b.ideal_px.size(), 100u);
  EXPECT_EQ(a.descriptors.type(), CV_8U);
  EXPECT_EQ(a.descriptors.rows, static_cast<int>(a.ideal_px.size()));
  int near = 0;
  for (const auto& p : b.ideal_px) {
    double best = 1e9;
    for (const auto& q : a.ideal_px) best = std::min<double>(best, std::hypot(p.x - q.x, p.y - q.y));
    near += best < 1.5;
  }
  EXPECT_GT(near, static_cast<int>(b.ideal_px.size()) / 3);
  // A working size caps the longest side.
  FeatureOptions small = options;
  small.max_side_px = 320;
  EXPECT_DOUBLE_EQ(WorkingScale(camera, small.max_side_px), 0.5);
}

TEST(FrameFeatures, AFlatFrameRetriesRelaxedAndDoesNotCrash) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 320, 240);
  const FrameFeatures f = DetectFeatures(cv::Mat(240, 320, CV_8U, cv::Scalar(90)), camera, FeatureOptions{});
  EXPECT_TRUE(f.relaxed);
  EXPECT_LT(f.ideal_px.size(), 10u);
}

TEST(GroundOffsets, PlaceTheSeabedPointWithThePosesPositionAndHeading) {
  // G = t + Rot(psi) a(p): the offsets with heading 0, turned and moved by
  // the pose, are where the full pose's homography puts each pixel.
  CameraModel camera = CameraFromFocalLength(8, 12.9, 640, 480);
  VehiclePose pose;
  pose.east_m = 3;
  pose.north_m = -2;
  pose.altitude_m = 1.9;
  pose.heading_deg = 123;
  pose.pitch_deg = 4;
  pose.roll_deg = -3;
  const std::vector<cv::Point2f> pixels{{10, 20}, {320, 240}, {600, 470}};
  const auto offsets = GroundOffsets(camera, pose, pixels);
  ASSERT_TRUE(offsets);
  const auto h = GroundFromImage(camera, pose);
  ASSERT_TRUE(h);
  for (size_t k = 0; k < pixels.size(); ++k) {
    const Eigen::Vector3d g = *h * Eigen::Vector3d(pixels[k].x, pixels[k].y, 1);
    const cv::Point2d expected(g.x() / g.z(), g.y() / g.z());
    const cv::Point2d got =
        cv::Point2d(pose.east_m, pose.north_m) + RotateClockwise((*offsets)[k], pose.heading_deg * M_PI / 180);
    EXPECT_NEAR(got.x, expected.x, 1e-9);
    EXPECT_NEAR(got.y, expected.y, 1e-9);
  }
  EXPECT_NEAR(WrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(-0.5), -0.5, 1e-12);
}

}  // namespace
}  // namespace seamap
