#include "core/camera/frame_projector.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kTol = 1e-9;

CameraModel SeedCamera() {
  return CameraFromFocalLength(8.0, 12.9, 696, 520);
}

VehiclePose Pose(double altitude, double heading = 0, double pitch = 0, double roll = 0) {
  VehiclePose p;
  p.altitude_m = altitude;
  p.heading_deg = heading;
  p.pitch_deg = pitch;
  p.roll_deg = roll;
  return p;
}

LocalXY Apply(const Eigen::Matrix3d& h, double u, double v) {
  const Eigen::Vector3d g = h * Eigen::Vector3d(u, v, 1);
  return {g.x() / g.z(), g.y() / g.z()};
}

LocalXY Centre(const CameraModel& c, const VehiclePose& pose) {
  return *PixelToGround(c, pose, c.cx, c.cy);
}

TEST(FrameProjectorTest, NedFromBodyFollowsAerospaceConvention) {
  // Heading 90: bow points east.
  EXPECT_TRUE((NedFromBody(Pose(1, 90)) * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d(0, 1, 0)));
  // Pitch +10 (bow up): bow gains an upward (negative down) component, and the
  // body down axis tilts forward: (sin, 0, cos).
  const Eigen::Matrix3d pitch = NedFromBody(Pose(1, 0, 10));
  EXPECT_LT((pitch * Eigen::Vector3d::UnitX()).z(), 0);
  EXPECT_TRUE(
      (pitch * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(std::sin(10 * kDeg), 0, std::cos(10 * kDeg))));
  // Roll +10 (starboard down): starboard gains a downward component, and the
  // body down axis tilts to port: (0, -sin, cos).
  const Eigen::Matrix3d roll = NedFromBody(Pose(1, 0, 0, 10));
  EXPECT_GT((roll * Eigen::Vector3d::UnitY()).z(), 0);
  EXPECT_TRUE(
      (roll * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(0, -std::sin(10 * kDeg), std::cos(10 * kDeg))));
}

TEST(FrameProjectorTest, NadirFootprintHasPinholeSize) {
  const CameraModel c = SeedCamera();
  const double alt = 10;
  const auto fp = Footprint(c, Pose(alt));
  ASSERT_TRUE(fp);
  const double half_w = 348 * alt / c.fx;  // cx + 0.5 pixels to the left edge
  const double half_h = 260 * alt / c.fy;
  const auto& [tl, tr, br, bl] = *fp;
  EXPECT_NEAR(tl.east, -half_w, kTol);  // image top-left: north-west
  EXPECT_NEAR(tl.north, half_h, kTol);
  EXPECT_NEAR(tr.east, half_w, kTol);
  EXPECT_NEAR(tr.north, half_h, kTol);
  EXPECT_NEAR(br.east, half_w, kTol);
  EXPECT_NEAR(br.north, -half_h, kTol);
  EXPECT_NEAR(bl.east, -half_w, kTol);
  EXPECT_NEAR(bl.north, -half_h, kTol);
  EXPECT_NEAR(tr.east - tl.east, c.width * alt / c.fx, kTol);
  EXPECT_NEAR(tl.north - bl.north, c.height * alt / c.fy, kTol);
  EXPECT_NEAR(GroundSampleDistance(c, alt), alt / c.fx, 1e-15);
}

TEST(FrameProjectorTest, ImageTopIsNorthAndRightIsEastAtHeadingZero) {
  const CameraModel c = SeedCamera();
  const auto top = PixelToGround(c, Pose(5), c.cx, 0);
  const auto right = PixelToGround(c, Pose(5), c.width - 1, c.cy);
  ASSERT_TRUE(top && right);
  EXPECT_GT(top->north, 1.0);
  EXPECT_NEAR(top->east, 0, kTol);
  EXPECT_GT(right->east, 1.0);
  EXPECT_NEAR(right->north, 0, kTol);
}

TEST(FrameProjectorTest, HeadingRotatesFootprintClockwise) {
  const CameraModel c = SeedCamera();
  const double alt = 10;
  const auto top = PixelToGround(c, Pose(alt, 90), c.cx, 0);
  const auto right = PixelToGround(c, Pose(alt, 90), c.width - 1, c.cy);
  ASSERT_TRUE(top && right);
  EXPECT_GT(top->east, 1.0);  // image top lies east
  EXPECT_NEAR(top->north, 0, kTol);
  EXPECT_LT(right->north, -1.0);  // image right lies south
  EXPECT_NEAR(right->east, 0, kTol);

  // Top-left corner (-a, +b) at heading 0 becomes (+b, +a) at heading 90.
  const auto fp = Footprint(c, Pose(alt, 90));
  ASSERT_TRUE(fp);
  EXPECT_NEAR((*fp)[0].east, 260 * alt / c.fy, kTol);
  EXPECT_NEAR((*fp)[0].north, 348 * alt / c.fx, kTol);
}

TEST(FrameProjectorTest, BowUpPitchMovesCentreAhead) {
  // Bow up tilts the body down axis forward, so the nadir camera looks ahead.
  const CameraModel c = SeedCamera();
  const double alt = 8;
  LocalXY centre = Centre(c, Pose(alt, 0, 10));
  EXPECT_NEAR(centre.north, alt * std::tan(10 * kDeg), kTol);
  EXPECT_NEAR(centre.east, 0, kTol);
  centre = Centre(c, Pose(alt, 90, 10));
  EXPECT_NEAR(centre.east, alt * std::tan(10 * kDeg), kTol);
  EXPECT_NEAR(centre.north, 0, kTol);
  // Same through the homography.
  const auto h = GroundFromImage(c, Pose(alt, 0, 10));
  ASSERT_TRUE(h);
  EXPECT_NEAR(Apply(*h, c.cx, c.cy).north, alt * std::tan(10 * kDeg), kTol);
}

TEST(FrameProjectorTest, StarboardDownRollMovesCentreToPort) {
  const CameraModel c = SeedCamera();
  const double alt = 8;
  LocalXY centre = Centre(c, Pose(alt, 0, 0, 10));
  EXPECT_NEAR(centre.east, -alt * std::tan(10 * kDeg), kTol);  // port = west at heading 0
  EXPECT_NEAR(centre.north, 0, kTol);
  centre = Centre(c, Pose(alt, 90, 0, 10));
  EXPECT_NEAR(centre.north, alt * std::tan(10 * kDeg), kTol);  // port = north at heading 90
  EXPECT_NEAR(centre.east, 0, kTol);
}

TEST(FrameProjectorTest, MountRotationComposesWithAttitude) {
  CameraModel c = SeedCamera();
  c.mount_rpy_deg = {0, 10, 0};  // camera tilted forward by 10 deg
  EXPECT_NEAR(Centre(c, Pose(5)).north, 5 * std::tan(10 * kDeg), kTol);
  const LocalXY level = Centre(c, Pose(5, 0, -10));  // bow down 10 cancels it
  EXPECT_NEAR(level.north, 0, kTol);
  EXPECT_NEAR(level.east, 0, kTol);

  c.mount_rpy_deg = {0, 0, 90};  // image right turned to aft
  const auto right = PixelToGround(c, Pose(5), c.width - 1, c.cy);
  ASSERT_TRUE(right);
  EXPECT_LT(right->north, -1.0);
  EXPECT_NEAR(right->east, 0, kTol);
}

TEST(FrameProjectorTest, MountOffsetAndVehiclePositionShiftFootprint) {
  const CameraModel nadir = SeedCamera();
  CameraModel offset = nadir;
  offset.mount_offset_m = {1.0, 0.5, 0.0};  // 1 m forward, 0.5 m starboard
  for (double heading : {0.0, 90.0}) {
    VehiclePose pose = Pose(6, heading);
    pose.east_m = 100;
    pose.north_m = -50;
    const auto a = Footprint(nadir, pose);
    const auto b = Footprint(offset, pose);
    ASSERT_TRUE(a && b);
    // Heading 0: forward = north, starboard = east. Heading 90: forward = east, starboard = south.
    const double de = heading == 0 ? 0.5 : 1.0;
    const double dn = heading == 0 ? 1.0 : -0.5;
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR((*b)[i].east - (*a)[i].east, de, kTol);
      EXPECT_NEAR((*b)[i].north - (*a)[i].north, dn, kTol);
    }
    const LocalXY centre = Centre(nadir, pose);
    EXPECT_NEAR(centre.east, 100, kTol);
    EXPECT_NEAR(centre.north, -50, kTol);
  }
  // A camera 2 m below the reference point sees a smaller patch.
  CameraModel low = nadir;
  low.mount_offset_m = {0, 0, 2};
  const auto fp = Footprint(low, Pose(10));
  ASSERT_TRUE(fp);
  EXPECT_NEAR((*fp)[1].east - (*fp)[0].east, nadir.width * 8 / nadir.fx, kTol);
}

TEST(FrameProjectorTest, DistortedPixelLandsWhereItsUndistortedPixelDoes) {
  CameraModel c = SeedCamera();
  c.distortion = {-0.25, 0.08, 0.001, -0.0015, 0.01};
  VehiclePose pose = Pose(7, 33, 4, -6);
  pose.east_m = 12;
  pose.north_m = 34;
  const auto h = GroundFromImage(c, pose);
  ASSERT_TRUE(h);
  for (const cv::Point2d ideal : {cv::Point2d(30, 40), cv::Point2d(650, 480), cv::Point2d(347.5, 10)}) {
    const cv::Point2d raw = c.Distort({ideal}).front();
    ASSERT_GT(cv::norm(raw - ideal), 0.5);
    const auto g = PixelToGround(c, pose, raw.x, raw.y);
    ASSERT_TRUE(g);
    const LocalXY expected = Apply(*h, ideal.x, ideal.y);
    EXPECT_NEAR(g->east, expected.east, 1e-6);
    EXPECT_NEAR(g->north, expected.north, 1e-6);
  }
  // The footprint uses undistorted corners: barrel distortion (k1 < 0) makes
  // the raw corners see a wider patch than the pinhole corners.
  CameraModel pinhole = c;
  pinhole.distortion = {};
  const auto wide = Footprint(c, Pose(7));
  const auto narrow = Footprint(pinhole, Pose(7));
  ASSERT_TRUE(wide && narrow);
  EXPECT_GT((*wide)[1].east - (*wide)[0].east, (*narrow)[1].east - (*narrow)[0].east + 0.1);
  const auto corner = PixelToGround(c, Pose(7), -0.5, -0.5);
  ASSERT_TRUE(corner);
  EXPECT_NEAR((*wide)[0].east, corner->east, 1e-6);
  EXPECT_NEAR((*wide)[0].north, corner->north, 1e-6);
}

TEST(FrameProjectorTest, HomographyAgreesWithPerPixelRays) {
  CameraModel c = SeedCamera();
  c.mount_rpy_deg = {2, -3, 5};
  c.mount_offset_m = {0.4, -0.2, 0.3};
  VehiclePose pose = Pose(9, 217, 6, -4);
  pose.east_m = -20;
  pose.north_m = 7;
  const auto h = GroundFromImage(c, pose);
  ASSERT_TRUE(h);
  EXPECT_NEAR((*h * Eigen::Vector3d(c.cx, c.cy, 1)).z(), 1.0, 1e-12);  // normalised
  for (double u : {-0.5, 100.0, 347.5, 695.5})
    for (double v : {-0.5, 200.0, 519.5}) {
      const auto g = PixelToGround(c, pose, u, v);
      ASSERT_TRUE(g);
      EXPECT_GT((*h * Eigen::Vector3d(u, v, 1)).z(), 0);
      const LocalXY expected = Apply(*h, u, v);
      EXPECT_NEAR(g->east, expected.east, 1e-9);
      EXPECT_NEAR(g->north, expected.north, 1e-9);
    }
}

TEST(FrameProjectorTest, HorizonAndBuriedCameraGiveNothing) {
  const CameraModel c = SeedCamera();  // vertical half field of view ~22.8 deg
  const double alt = 4;
  // Bow up 80 deg: the optical axis is 10 deg below the horizon, the image top above it.
  EXPECT_FALSE(GroundFromImage(c, Pose(alt, 0, 80)));
  EXPECT_FALSE(Footprint(c, Pose(alt, 0, 80)));
  EXPECT_FALSE(PixelToGround(c, Pose(alt, 0, 80), c.cx, 0));
  const auto centre = PixelToGround(c, Pose(alt, 0, 80), c.cx, c.cy);
  ASSERT_TRUE(centre);
  EXPECT_NEAR(centre->north, alt / std::tan(10 * kDeg), 1e-9);
  // A 60 deg pitch still sees the seabed with the whole frame.
  EXPECT_TRUE(GroundFromImage(c, Pose(alt, 0, 60)));

  CameraModel buried = c;
  buried.mount_offset_m = {0, 0, 5};  // camera 5 m below the reference, seabed at 3 m
  EXPECT_FALSE(GroundFromImage(buried, Pose(3)));
  EXPECT_FALSE(PixelToGround(buried, Pose(3), c.cx, c.cy));
}

}  // namespace
}  // namespace seamap
