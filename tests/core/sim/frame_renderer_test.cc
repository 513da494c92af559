#include "core/sim/frame_renderer.h"

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/sim/ground_truth.h"
#include "core/sim/seabed_texture.h"

namespace seamap {
namespace {

// 160x120 pinhole camera, principal point on a pixel centre.
CameraModel SmallCamera() {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 140;
  c.cx = 80;
  c.cy = 60;
  return c;
}

// A 4 x 4 m procedural seabed centred on the origin, 4 mm per pixel (finer
// than the 160x120 frames' ~13 mm GSD).
SeabedTexture SmallTexture(bool color = false, int bit_depth = 8) {
  SeabedTexture t;
  t.res_m = 0.004;
  t.image = MakeProceduralTexture({1000, 1000}, t.res_m, color, bit_depth, 11);
  t.east_min = -2;
  t.north_max = 2;
  return t;
}

GroundTruth AsTruth(const SeabedTexture& t) {
  GroundTruth g;
  g.image = t.image;
  g.res_m = t.res_m;
  g.east_min = t.east_min;
  g.north_max = t.north_max;
  return g;
}

VehiclePose Pose(double heading = 0, double pitch = 0, double roll = 0) {
  VehiclePose p;
  p.east_m = 0.123;
  p.north_m = -0.234;
  p.altitude_m = 1.8;
  p.heading_deg = heading;
  p.pitch_deg = pitch;
  p.roll_deg = roll;
  return p;
}

float TruthAt(const SeabedTexture& t, double east, double north) {
  cv::Vec3f v;
  EXPECT_TRUE(AsTruth(t).Sample({east, north}, &v));
  return v[0];
}

// Pixels of a 9x7 grid over the frame, compared with the texture at ground
// points the test computes itself from pinhole geometry.
template <typename GroundOf>
void ExpectFrameMatches(const cv::Mat& frame, const SeabedTexture& t, GroundOf ground_of) {
  double sum = 0, worst = 0;
  int n = 0;
  for (int v = 5; v < frame.rows; v += 18)
    for (int u = 5; u < frame.cols; u += 18) {
      const cv::Point2d g = ground_of(u, v);
      const double err = std::fabs(frame.at<uint8_t>(v, u) - TruthAt(t, g.x, g.y));
      sum += err, worst = std::max(worst, err), ++n;
    }
  // Only remap's 1/32 pixel quantisation and rounding separate the two.
  EXPECT_LT(sum / n, 1.0);
  EXPECT_LT(worst, 4.0);
}

TEST(FrameRendererTest, NadirFrameSeesTheTextureUnderTheVehicle) {
  const SeabedTexture t = SmallTexture();
  const CameraModel cam = SmallCamera();
  const VehiclePose pose = Pose();
  const cv::Mat frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  ASSERT_EQ(frame.type(), CV_8UC1);
  ASSERT_EQ(frame.size(), cv::Size(160, 120));
  EXPECT_NEAR(frame.at<uint8_t>(60, 80), TruthAt(t, pose.east_m, pose.north_m), 1.5);
  // Heading 0: image right is east, image down is south.
  ExpectFrameMatches(frame, t, [&](int u, int v) {
    return cv::Point2d(pose.east_m + (u - cam.cx) / cam.fx * pose.altitude_m,
                       pose.north_m - (v - cam.cy) / cam.fy * pose.altitude_m);
  });
  // The test would notice a one-pixel shift.
  cv::Mat shifted;
  cv::warpAffine(frame, shifted, cv::Matx23d(1, 0, 1, 0, 1, 0), frame.size());
  EXPECT_GT(cv::norm(shifted(cv::Rect(2, 0, 150, 120)), frame(cv::Rect(2, 0, 150, 120)), cv::NORM_L1) / (150 * 120),
            3.0);
}

TEST(FrameRendererTest, HeadingEastTurnsTheImage) {
  const SeabedTexture t = SmallTexture();
  const CameraModel cam = SmallCamera();
  const VehiclePose pose = Pose(90);
  const cv::Mat frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  // Heading 90: image top is east (the bow), image right is south (starboard).
  ExpectFrameMatches(frame, t, [&](int u, int v) {
    return cv::Point2d(pose.east_m - (v - cam.cy) / cam.fy * pose.altitude_m,
                       pose.north_m - (u - cam.cx) / cam.fx * pose.altitude_m);
  });
}

TEST(FrameRendererTest, PitchAndRollMoveTheCentreOfView) {
  const SeabedTexture t = SmallTexture();
  const CameraModel cam = SmallCamera();
  // Bow up 10 deg: the optical axis points ahead (north) by alt * tan(10 deg).
  VehiclePose pose = Pose(0, 10, 0);
  cv::Mat frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  EXPECT_NEAR(frame.at<uint8_t>(60, 80),
              TruthAt(t, pose.east_m, pose.north_m + pose.altitude_m * std::tan(10 * M_PI / 180)), 1.5);
  // Starboard down 8 deg: the axis points to port (west).
  pose = Pose(0, 0, 8);
  frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  EXPECT_NEAR(frame.at<uint8_t>(60, 80),
              TruthAt(t, pose.east_m - pose.altitude_m * std::tan(8 * M_PI / 180), pose.north_m), 1.5);
}

TEST(FrameRendererTest, MountOffsetMovesAndScalesTheView) {
  const SeabedTexture t = SmallTexture();
  CameraModel cam = SmallCamera();
  cam.mount_offset_m = {0.3, -0.2, 0.4};  // forward, to port, below the nav point
  const VehiclePose pose = Pose();
  const cv::Mat frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  const double height = pose.altitude_m - 0.4;
  ExpectFrameMatches(frame, t, [&](int u, int v) {
    return cv::Point2d(pose.east_m - 0.2 + (u - cam.cx) / cam.fx * height,
                       pose.north_m + 0.3 - (v - cam.cy) / cam.fy * height);
  });
}

TEST(FrameRendererTest, DistortionFollowsTheBrownModel) {
  const SeabedTexture t = SmallTexture();
  CameraModel cam = SmallCamera();
  cam.distortion = {-0.2, 0.05, 0, 0, 0};
  const VehiclePose pose = Pose();
  const cv::Mat frame = FrameRenderer(cam, {}).Render(t, pose, 1);
  // Raw pixel -> distorted normalised point -> undistorted ray, inverting
  // x_d = x (1 + k1 r^2 + k2 r^4) by fixed-point iteration.
  ExpectFrameMatches(frame, t, [&](int u, int v) {
    const double xd = (u - cam.cx) / cam.fx, yd = (v - cam.cy) / cam.fy;
    double x = xd, y = yd;
    for (int i = 0; i < 100; ++i) {
      const double r2 = x * x + y * y;
      const double radial = 1 + cam.distortion[0] * r2 + cam.distortion[1] * r2 * r2;
      x = xd / radial, y = yd / radial;
    }
    return cv::Point2d(pose.east_m + x * pose.altitude_m, pose.north_m - y * pose.altitude_m);
  });
  // And it differs from the pinhole frame away from the centre.
  const cv::Mat pinhole = FrameRenderer(SmallCamera(), {}).Render(t, pose, 1);
  const cv::Rect corner(0, 0, 30, 20);
  EXPECT_GT(cv::norm(frame(corner), pinhole(corner), cv::NORM_L1) / corner.area(), 5);
}

TEST(FrameRendererTest, GroundBoundsMatchTheFootprint) {
  const CameraModel cam = SmallCamera();
  const VehiclePose pose = Pose();
  cv::Rect2d b;
  ASSERT_TRUE(FrameRenderer(cam, {}).GroundBounds(pose, &b));
  EXPECT_NEAR(b.width, 159 / 140.0 * 1.8, 1e-5);
  EXPECT_NEAR(b.height, 119 / 140.0 * 1.8, 1e-5);
  EXPECT_NEAR(b.x, pose.east_m - 80 / 140.0 * 1.8, 1e-5);
  EXPECT_FALSE(FrameRenderer(cam, {}).GroundBounds(Pose(0, 80, 0), &b));  // sees the horizon
}

TEST(FrameRendererTest, DegradationsAreOffByDefault) {
  EXPECT_FALSE(Degradations{}.Any());
  EXPECT_TRUE(Degradations::Moderate().Any());
  const SeabedTexture t = SmallTexture();
  const cv::Mat a = FrameRenderer(SmallCamera(), {}).Render(t, Pose(), 1);
  // Without degradations a frame is exactly the texture resampled: same as with zero strengths.
  const cv::Mat b = FrameRenderer(SmallCamera(), Degradations{0, 0, 0, 0}).Render(t, Pose(), 2);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0);
}

double Mean(const cv::Mat& m, int channel = 0) {
  return cv::mean(m)[channel];
}

TEST(FrameRendererTest, VignettingDarkensCornersMoreThanTheCentre) {
  const SeabedTexture t = SmallTexture();
  const cv::Mat clean = FrameRenderer(SmallCamera(), {}).Render(t, Pose(), 1);
  Degradations d;
  d.vignetting = 0.8;
  const cv::Mat lit = FrameRenderer(SmallCamera(), d).Render(t, Pose(), 1);
  const cv::Rect centre(60, 45, 40, 30), corner(0, 0, 30, 20);
  const double centre_ratio = Mean(lit(centre)) / Mean(clean(centre));
  const double corner_ratio = Mean(lit(corner)) / Mean(clean(corner));
  EXPECT_GT(centre_ratio, 0.9);
  EXPECT_LT(corner_ratio, 0.6);
}

TEST(FrameRendererTest, ColorCastLowersRedMostly) {
  const SeabedTexture t = SmallTexture(true);
  const cv::Mat clean = FrameRenderer(SmallCamera(), {}).Render(t, Pose(), 1);
  ASSERT_EQ(clean.type(), CV_8UC3);
  Degradations d;
  d.color_cast = 1;
  const cv::Mat cast = FrameRenderer(SmallCamera(), d).Render(t, Pose(), 1);
  const double red = Mean(cast, 2) / Mean(clean, 2), blue = Mean(cast, 0) / Mean(clean, 0);
  EXPECT_LT(red, 0.5);
  EXPECT_GT(blue, 0.85);
  EXPECT_LT(blue, 1.0);
}

TEST(FrameRendererTest, HazeLowersContrastTowardsBluishWater) {
  const SeabedTexture t = SmallTexture(true);
  const cv::Mat clean = FrameRenderer(SmallCamera(), {}).Render(t, Pose(), 1);
  Degradations d;
  d.haze = 1;
  const cv::Mat hazy = FrameRenderer(SmallCamera(), d).Render(t, Pose(), 1);
  cv::Scalar m0, s0, m1, s1;
  cv::meanStdDev(clean, m0, s0);
  cv::meanStdDev(hazy, m1, s1);
  EXPECT_LT(s1[1], 0.7 * s0[1]);
  EXPECT_GT(m1[0] - m1[2], m0[0] - m0[2] + 20);  // bluer than red
}

TEST(FrameRendererTest, NoiseRaisesVarianceReproducibly) {
  const SeabedTexture t = SmallTexture();
  const cv::Mat clean = FrameRenderer(SmallCamera(), {}).Render(t, Pose(), 1);
  Degradations d;
  d.noise_sigma = 4;
  const FrameRenderer noisy(SmallCamera(), d);
  const cv::Mat a = noisy.Render(t, Pose(), 5), b = noisy.Render(t, Pose(), 5), c = noisy.Render(t, Pose(), 6);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0);
  cv::Mat diff;
  cv::subtract(a, clean, diff, cv::noArray(), CV_32F);
  cv::Scalar mean, sd;
  cv::meanStdDev(diff, mean, sd);
  EXPECT_NEAR(sd[0], 4, 0.3);
  EXPECT_NEAR(mean[0], 0, 0.2);
}

TEST(FrameRendererTest, SixteenBitTextureGivesSixteenBitFrames) {
  const cv::Mat f8 = FrameRenderer(SmallCamera(), {}).Render(SmallTexture(false, 8), Pose(), 1);
  const cv::Mat f16 = FrameRenderer(SmallCamera(), {}).Render(SmallTexture(false, 16), Pose(), 1);
  ASSERT_EQ(f16.type(), CV_16UC1);
  cv::Mat f16_as_8;
  f16.convertTo(f16_as_8, CV_8U, 1 / 257.0);
  EXPECT_LT(cv::norm(f16_as_8, f8, cv::NORM_L1) / f8.total(), 1.0);
  double lo, hi;
  cv::minMaxLoc(f16, &lo, &hi);
  EXPECT_GT(hi, 20000);
  // Degradations keep the depth and scale.
  Degradations d;
  d.noise_sigma = 1;
  const cv::Mat n16 = FrameRenderer(SmallCamera(), d).Render(SmallTexture(false, 16), Pose(), 1);
  ASSERT_EQ(n16.type(), CV_16UC1);
  EXPECT_NEAR(Mean(n16), Mean(f16), 200);
}

}  // namespace
}  // namespace seamap
