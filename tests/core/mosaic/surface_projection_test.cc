#include "core/mosaic/surface_projection.h"

#include <cmath>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "core/mosaic/box_mapping.h"
#include "core/mosaic/frame_warper.h"

namespace seamap {
namespace {

CameraModel TestCamera() {
  CameraModel c = CameraFromFocalLength(8, 12.9, 320, 240);
  c.distortion = {-0.05, 0.01, 0.001, -0.0005, 0};
  c.mount_offset_m = {0.3, -0.1, 0.05};
  return c;
}

VehiclePose TestPose() {
  VehiclePose p;
  p.east_m = 1.2;
  p.north_m = -0.7;
  p.depth_m = 33;
  p.altitude_m = 2;
  p.heading_deg = 37;
  p.pitch_deg = 3;
  p.roll_deg = -2;
  return p;
}

// A grid of 4 x 4 m at 2 cm around the pose's nadir, heights from `up(east, north)`.
template <typename Up>
std::shared_ptr<HeightGrid> GridOf(Up up) {
  auto g = std::make_shared<HeightGrid>();
  g->cell_m = 0.02;
  g->east0_m = -1;
  g->north0_m = 1.5;
  g->height_m = cv::Mat1f(201, 201);
  g->sigma_m = cv::Mat1f(201, 201, 0.01f);
  for (int r = 0; r < g->rows(); ++r)
    for (int c = 0; c < g->cols(); ++c) {
      const LocalXY p = g->CellCentre(r, c);
      g->height_m(r, c) = static_cast<float>(up(p.east, p.north));
    }
  return g;
}

struct Fixture {
  CameraModel camera = TestCamera();
  LocalFrame frame{LatLon{43.1, 131.9}};
  SeabedProjection flat{camera, frame, 25, 256};
};

TEST(SurfaceProjection, AFlatSurfaceMapsAsThePlaneDoes) {
  // The surface at the frame's own seabed (altitude_m below the vehicle),
  // then 0.4 m higher (the plane of a frame 0.4 m lower): every grid point of
  // the box maps to the raw image as the flat projection maps it.
  Fixture f;
  for (const double raise_m : {0.0, 0.4}) {
    const VehiclePose pose = TestPose();
    const double seabed_up = -(pose.depth_m + pose.altitude_m) + raise_m;
    const SurfaceProjection surface(f.flat, GridOf([&](double, double) { return seabed_up; }));
    VehiclePose as_plane = pose;
    as_plane.altitude_m -= raise_m;
    const auto outline = surface.Outline(pose);
    const auto plane_outline = f.flat.Outline(as_plane);
    ASSERT_TRUE(outline && plane_outline);
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(outline->corners[i].x, plane_outline->corners[i].x, 1e-2) << raise_m;
      EXPECT_NEAR(outline->corners[i].y, plane_outline->corners[i].y, 1e-2) << raise_m;
    }
    const auto maps = surface.Mappings(*outline, {pose});
    ASSERT_EQ(maps.size(), 1u);
    const PlaneMapping plane(f.flat, f.flat.CameraFromBox(*plane_outline, outline->box[0], outline->box[1]));
    int compared = 0;
    for (int y = 0; y < outline->box[3]; y += 37)
      for (int x = 0; x < outline->box[2]; x += 37) {
        const RawPosition a = maps[0]->ToRaw(x, y), b = plane.ToRaw(x, y);
        ASSERT_EQ(a.valid, b.valid) << x << "," << y;
        if (!a.valid) continue;
        EXPECT_NEAR(a.u, b.u, 0.02) << raise_m << " at " << x << "," << y;
        EXPECT_NEAR(a.v, b.v, 0.02) << raise_m << " at " << x << "," << y;
        ++compared;
      }
    EXPECT_GT(compared, 50);
  }
}

TEST(SurfaceProjection, APointOnTheReliefLandsOnThePixelThatSeesIt) {
  // Relief: a smooth mound. Cast the ray of a raw pixel onto it (an
  // independent path: undistort, ray, march); the map pixel where it lands
  // maps back to that raw pixel.
  Fixture f;
  const VehiclePose pose = TestPose();
  const double floor_up = -(pose.depth_m + pose.altitude_m);
  auto grid = GridOf([&](double e, double n) {
    return floor_up + 0.5 * std::exp(-((e - 1.3) * (e - 1.3) + (n + 0.6) * (n + 0.6)) / 0.1);
  });
  const SurfaceProjection surface(f.flat, grid);
  const auto outline = surface.Outline(pose);
  ASSERT_TRUE(outline);
  const auto maps = surface.Mappings(*outline, {pose});
  const CameraPlacement cam = PlaceCamera(f.camera, pose);
  const auto tangent = f.flat.TangentAt({pose.east_m, pose.north_m});
  for (const cv::Point2d raw : {cv::Point2d(160, 120), cv::Point2d(40, 30), cv::Point2d(290, 200)}) {
    const cv::Point2d ideal = f.camera.Undistort({raw}).front();
    const Eigen::Vector3d ray =
        cam.camera_from_enu.transpose() *
        Eigen::Vector3d((ideal.x - f.camera.cx) / f.camera.fx, (ideal.y - f.camera.cy) / f.camera.fy, 1);
    Eigen::Vector3d p = cam.eye_enu;
    double h = 0;
    while (grid->Sample({p.x(), p.y()}, &h) && p.z() > h) p += ray * 1e-5;  // 10 um steps
    const cv::Point2d map = tangent.ToMap({p.x(), p.y()}) - cv::Point2d(0.5 + outline->box[0], 0.5 + outline->box[1]);
    const RawPosition back = maps[0]->ToRaw(map.x, map.y);
    ASSERT_TRUE(back.valid) << raw;
    EXPECT_NEAR(back.u, raw.x, 0.05) << raw;
    EXPECT_NEAR(back.v, raw.y, 0.05) << raw;
  }
}

TEST(SurfaceProjection, GroundHiddenBehindARidgeIsRefusedAndSeenFromTheOtherSide) {
  // A ridge 0.6 m high running north, 0.3 m east of the vehicle: the floor
  // just east of it is hidden from this camera and seen from one 1 m east.
  Fixture f;
  f.camera.mount_offset_m = Eigen::Vector3d::Zero();
  VehiclePose west = TestPose();
  west.heading_deg = 0, west.pitch_deg = 0, west.roll_deg = 0;
  VehiclePose east = west;
  east.east_m += 1.0;
  const double floor_up = -(west.depth_m + west.altitude_m);
  const double ridge_e = west.east_m + 0.3;
  auto grid = GridOf([&](double e, double) { return std::fabs(e - ridge_e) < 0.04 ? floor_up + 0.6 : floor_up; });
  const SurfaceProjection surface(f.flat, grid);
  const auto outline = surface.Outline(west);
  ASSERT_TRUE(outline);
  const auto maps = surface.Mappings(*outline, {west, east});
  ASSERT_EQ(maps.size(), 2u);
  const auto tangent = f.flat.TangentAt({west.east_m, west.north_m});
  auto box_pixel = [&](double e, double n) {
    return tangent.ToMap({e, n}) - cv::Point2d(0.5 + outline->box[0], 0.5 + outline->box[1]);
  };
  const cv::Point2d hidden = box_pixel(ridge_e + 0.12, west.north_m);  // in the ridge's shadow from the west
  const cv::Point2d open = box_pixel(ridge_e - 0.12, west.north_m);
  EXPECT_FALSE(maps[0]->ToRaw(hidden.x, hidden.y).valid);
  EXPECT_TRUE(maps[1]->ToRaw(hidden.x, hidden.y).valid);
  EXPECT_TRUE(maps[0]->ToRaw(open.x, open.y).valid);
}

TEST(SurfaceProjection, HolesFallBackToTheFramesPlane) {
  Fixture f;
  const VehiclePose pose = TestPose();
  auto grid = GridOf([](double, double) { return std::numeric_limits<double>::quiet_NaN(); });
  const SurfaceProjection surface(f.flat, grid);
  const auto outline = surface.Outline(pose);
  const auto plane_outline = f.flat.Outline(pose);
  ASSERT_TRUE(outline && plane_outline);
  const auto maps = surface.Mappings(*outline, {pose});
  const PlaneMapping plane(f.flat, f.flat.CameraFromBox(*plane_outline, outline->box[0], outline->box[1]));
  for (int y = 10; y < outline->box[3]; y += 53)
    for (int x = 10; x < outline->box[2]; x += 53) {
      const RawPosition a = maps[0]->ToRaw(x, y), b = plane.ToRaw(x, y);
      ASSERT_EQ(a.valid, b.valid);
      EXPECT_NEAR(a.u, b.u, 0.02);
      EXPECT_NEAR(a.v, b.v, 0.02);
    }
}

TEST(SurfaceProjection, AWarpOntoAFlatSurfacePaintsAsTheFlatWarp) {
  // The whole warp (grid, weights, sampling) through the surface seam: on a
  // surface at the frame's own plane the painted pixels match the flat warp's.
  Fixture f;
  f.camera.distortion = {};
  VehiclePose pose = TestPose();
  cv::Mat image(f.camera.height, f.camera.width, CV_8UC1);
  cv::randu(image, 0, 255);
  WarpOptions o;
  const FrameWarper flat(f.camera, f.frame, 25, 256, o);
  const double seabed_up = -(pose.depth_m + pose.altitude_m);
  const FrameWarper relief(f.camera, f.frame, 25, 256, o, GridOf([&](double, double) { return seabed_up; }));
  const auto a = flat.Warp(image, pose), b = relief.Warp(image, pose);
  ASSERT_TRUE(a && b);
  int compared = 0, close = 0;
  for (int y = 0; y < a->weight.rows; ++y)
    for (int x = 0; x < a->weight.cols; ++x) {
      const int64_t bx = a->x0 + x - b->x0, by = a->y0 + y - b->y0;  // the same global pixel in b
      if (bx < 0 || by < 0 || bx >= b->weight.cols || by >= b->weight.rows) continue;
      if (a->weight.at<uint8_t>(y, x) < 30 || b->weight.at<uint8_t>(by, bx) < 30) continue;
      ++compared;
      close += std::abs(a->pixels.at<uint8_t>(y, x) - b->pixels.at<uint8_t>(by, bx)) <= 2;
    }
  EXPECT_GT(compared, 20000);
  EXPECT_GT(close, compared * 0.97);
}

}  // namespace
}  // namespace seamap
