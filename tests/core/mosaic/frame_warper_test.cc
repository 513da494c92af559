#include "core/mosaic/frame_warper.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

CameraModel TestCamera() {
  CameraModel c = CameraFromFocalLength(8, 12.9, 320, 240);
  return c;
}

// Global pixel of a warped frame's pixel with the highest value in one channel.
cv::Point2d Brightest(const WarpedFrame& f) {
  cv::Point p;
  cv::minMaxLoc(f.pixels, nullptr, nullptr, nullptr, &p, f.weight > 0);
  return {f.x0 + p.x + 0.5, f.y0 + p.y + 0.5};
}

TEST(FrameWarper, NadirFrameIsCentredOnTheVehicleAndNorthUp) {
  const LatLon origin{43.1, 131.9};
  LocalFrame frame(origin);
  CameraModel cam = TestCamera();
  const int zoom = 25;
  FrameWarper warper(cam, frame, zoom, 256, 1, 1.0);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  cv::Mat image(cam.height, cam.width, CV_8U, cv::Scalar(50));
  // A bright dot at the principal point, another in the top-left quadrant.
  cv::circle(image, {static_cast<int>(cam.cx + 0.5), static_cast<int>(cam.cy + 0.5)}, 2, 255, -1);
  auto warped = warper.Warp(image, pose);
  ASSERT_TRUE(warped);
  GlobalPixel expected = LatLonToPixel(origin, zoom, 256);
  cv::Point2d got = Brightest(*warped);
  EXPECT_NEAR(got.x, expected.x, 1.5);
  EXPECT_NEAR(got.y, expected.y, 1.5);

  // Size: footprint width / metres per pixel.
  const double mpp = MetersPerPixel(origin.lat, zoom, 256);
  EXPECT_NEAR(warped->pixels.cols, cam.width * pose.altitude_m / cam.fx / mpp, 2);
  EXPECT_NEAR(warped->pixels.rows, cam.height * pose.altitude_m / cam.fy / mpp, 2);

  // Image top is north: a dot near the top edge lands at smaller y.
  cv::Mat top(cam.height, cam.width, CV_8U, cv::Scalar(50));
  cv::circle(top, {cam.width / 2, 20}, 2, 255, -1);
  cv::Point2d top_px = Brightest(*warper.Warp(top, pose));
  EXPECT_LT(top_px.y, expected.y - 50);
  EXPECT_NEAR(top_px.x, expected.x, 2);
}

TEST(FrameWarper, HeadingEastTurnsImageTopEast) {
  LocalFrame frame({10, 20});
  CameraModel cam = TestCamera();
  FrameWarper warper(cam, frame, 25, 256, 1, 1.0);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  pose.heading_deg = 90;
  cv::Mat top(cam.height, cam.width, CV_8U, cv::Scalar(50));
  cv::circle(top, {cam.width / 2, 20}, 2, 255, -1);
  auto warped = warper.Warp(top, pose);
  ASSERT_TRUE(warped);
  GlobalPixel centre = LatLonToPixel({10, 20}, 25, 256);
  cv::Point2d p = Brightest(*warped);
  EXPECT_GT(p.x, centre.x + 50);
  EXPECT_NEAR(p.y, centre.y, 2);
}

TEST(FrameWarper, WeightIsHighestInTheCentreAndZeroOutside) {
  LocalFrame frame({10, 20});
  CameraModel cam = TestCamera();
  FrameWarper warper(cam, frame, 25, 256, 1, 1.0);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  pose.heading_deg = 30;  // rotated: bounding-box corners are outside the frame
  auto warped = warper.Warp(cv::Mat(cam.height, cam.width, CV_8U, cv::Scalar(80)), pose);
  ASSERT_TRUE(warped);
  const cv::Mat& weight = warped->weight;
  EXPECT_EQ(weight.at<uint8_t>(0, 0), 0);
  EXPECT_GT(weight.at<uint8_t>(weight.rows / 2, weight.cols / 2), 240);
}

TEST(FrameWarper, ToEightBitHandlesDepthsAndChannels) {
  cv::Mat sixteen(2, 2, CV_16U, cv::Scalar(65535));
  EXPECT_EQ(ToEightBit(sixteen, 1, 65535).at<uint8_t>(0, 0), 255);
  EXPECT_EQ(ToEightBit(sixteen, 1, 4095).type(), CV_8U);
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(10, 10, 10));
  EXPECT_EQ(ToEightBit(bgr, 1, 65535).type(), CV_8UC1);
  cv::Mat gray_alpha(2, 2, CV_8UC2, cv::Scalar(7, 255));
  EXPECT_EQ(ToEightBit(gray_alpha, 3, 65535).type(), CV_8UC3);
}

}  // namespace
}  // namespace seamap
