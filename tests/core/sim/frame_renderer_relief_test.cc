// FrameRenderer on a rugged seabed (SetTerrain), checked against pinhole
// projections the test computes itself; and the flat path pinned byte for byte.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/sim/frame_renderer.h"
#include "core/sim/seabed_texture.h"
#include "core/terrain/height_grid.h"

namespace seamap {
namespace {

constexpr double kSeabedUp_m = -35;

CameraModel SmallCamera(bool distorted) {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 140;
  c.cx = 80;
  c.cy = 60;
  if (distorted) c.distortion = {-0.05, 0.01, 0, 0, 0};
  return c;
}

// A 4 x 4 m seabed centred on the origin: heights from `height(east, north)` on 1 cm cells.
template <typename F>
HeightGrid Terrain(F height) {
  HeightGrid g;
  g.cell_m = 0.01;
  g.east0_m = -2 + g.cell_m / 2;
  g.north0_m = 2 - g.cell_m / 2;
  g.height_m.create(400, 400);
  for (int r = 0; r < 400; ++r)
    for (int c = 0; c < 400; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(height(p.east, p.north));
    }
  g.sigma_m = cv::Mat1f(400, 400, 0.f);
  return g;
}

// A gray 4 x 4 m texture, 2 mm per pixel, value `background`.
SeabedTexture PlainTexture(uint8_t background) {
  SeabedTexture t;
  t.res_m = 0.002;
  t.image = cv::Mat(2000, 2000, CV_8UC1, cv::Scalar(background));
  t.east_min = -2;
  t.north_max = 2;
  return t;
}

// A dark gaussian dot (sigma 1.5 cm) painted at a local point.
void PaintDot(SeabedTexture* t, double east, double north) {
  const double col = t->Column(east), row = t->Row(north), sigma_px = 0.015 / t->res_m;
  for (int r = static_cast<int>(row - 4 * sigma_px); r <= row + 4 * sigma_px; ++r)
    for (int c = static_cast<int>(col - 4 * sigma_px); c <= col + 4 * sigma_px; ++c) {
      const double d2 = ((r - row) * (r - row) + (c - col) * (c - col)) / (sigma_px * sigma_px);
      uint8_t& v = t->image.at<uint8_t>(r, c);
      v = static_cast<uint8_t>(std::lround(v * (1 - 0.9 * std::exp(-d2 / 2))));
    }
}

VehiclePose Pose(double pitch, double roll) {
  VehiclePose p;
  p.east_m = 0.05;
  p.north_m = -0.08;
  p.depth_m = 33;    // 2 m above the mean seabed
  p.altitude_m = 2;  // not used over a terrain
  p.heading_deg = 30;
  p.pitch_deg = pitch;
  p.roll_deg = roll;
  return p;
}

// Raw pixel of a local 3-D point (east, north, up), by the pinhole model
// and the camera's distortion: independent of the renderer's ray casting.
cv::Point2d Project(const CameraModel& camera, const VehiclePose& pose, const Eigen::Vector3d& enu) {
  const Eigen::Vector3d ned(enu.y() - pose.north_m, enu.x() - pose.east_m, -enu.z() - pose.depth_m);
  const Eigen::Vector3d cam = NedFromCamera(camera, pose).transpose() * ned;
  const cv::Point2d ideal(camera.fx * cam.x() / cam.z() + camera.cx, camera.fy * cam.y() / cam.z() + camera.cy);
  return camera.Distort({ideal})[0];
}

// Centroid of darkness (background - value) in a window around `guess`.
cv::Point2d DarkCentroid(const cv::Mat& frame, cv::Point2d guess, double background) {
  double sx = 0, sy = 0, sw = 0;
  for (int v = static_cast<int>(guess.y) - 6; v <= guess.y + 6; ++v)
    for (int u = static_cast<int>(guess.x) - 6; u <= guess.x + 6; ++u) {
      const double w = std::max(0.0, background - frame.at<uint8_t>(v, u) - 2.0);
      sx += w * u, sy += w * v, sw += w;
    }
  return sw > 0 ? cv::Point2d(sx / sw, sy / sw) : cv::Point2d(-1, -1);
}

uint64_t Fnv1a(const cv::Mat& m) {
  uint64_t h = 1469598103934665603ull;
  for (int r = 0; r < m.rows; ++r) {
    const uint8_t* p = m.ptr<uint8_t>(r);
    for (size_t i = 0; i < m.cols * m.elemSize(); ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  return h;
}

TEST(FrameRendererReliefTest, DotsOnBumpsAppearWhereThePinholeProjectsThem) {
  // Two bumps 0.4 and 0.25 m high, dots on their tops, flanks and the plain.
  const auto height = [](double e, double n) {
    return kSeabedUp_m + 0.4 * std::exp(-((e - 0.3) * (e - 0.3) + (n - 0.2) * (n - 0.2)) / 0.08) +
           0.25 * std::exp(-((e + 0.4) * (e + 0.4) + (n + 0.3) * (n + 0.3)) / 0.05);
  };
  const HeightGrid terrain = Terrain(height);
  SeabedTexture texture = PlainTexture(200);
  const std::vector<LocalXY> dots = {{0.3, 0.2},     {0.5, 0.3},  {0.1, 0.05},  {-0.4, -0.3},
                                     {-0.25, -0.45}, {0.6, -0.4}, {-0.6, 0.35}, {0.05, 0.5}};
  for (const LocalXY& d : dots) PaintDot(&texture, d.east, d.north);
  for (const bool distorted : {false, true}) {
    const CameraModel camera = SmallCamera(distorted);
    FrameRenderer renderer(camera, {});
    renderer.SetTerrain(terrain);
    const VehiclePose pose = Pose(4, -3);
    const cv::Mat frame = renderer.Render(texture, pose, 1);
    double worst = 0;
    for (const LocalXY& d : dots) {
      double up = 0;
      ASSERT_TRUE(terrain.Sample(d, &up));
      const cv::Point2d expected = Project(camera, pose, {d.east, d.north, up});
      ASSERT_TRUE(expected.x > 8 && expected.y > 8 && expected.x < 152 && expected.y < 112);
      const cv::Point2d seen = DarkCentroid(frame, expected, 200);
      worst = std::max(worst, std::hypot(seen.x - expected.x, seen.y - expected.y));
    }
    EXPECT_LT(worst, 0.5) << (distorted ? "distorted" : "pinhole");
    // The plane path would put the raised dots elsewhere: the test can fail.
    FrameRenderer flat(camera, {});
    const cv::Mat flat_frame = flat.Render(texture, pose, 1);
    double up = 0;
    terrain.Sample(dots[0], &up);
    const cv::Point2d expected = Project(camera, pose, {dots[0].east, dots[0].north, up});
    const cv::Point2d on_plane = DarkCentroid(flat_frame, expected, 200);
    EXPECT_GT(std::hypot(on_plane.x - expected.x, on_plane.y - expected.y), 1.5);
  }
}

TEST(FrameRendererReliefTest, ABumpHidesWhatLiesBehindIt) {
  // A narrow 0.6 m bump at east 0.8, painted white; a dark dot on the plain behind it.
  const auto height = [](double e, double n) {
    return kSeabedUp_m + 0.6 * std::exp(-((e - 0.8) * (e - 0.8) + n * n) / 0.02);
  };
  const HeightGrid terrain = Terrain(height);
  SeabedTexture texture = PlainTexture(120);
  cv::circle(texture.image, cv::Point(static_cast<int>(texture.Column(0.8)), static_cast<int>(texture.Row(0))),
             static_cast<int>(0.15 / texture.res_m), cv::Scalar(250), cv::FILLED);
  const Eigen::Vector3d dot(1.05, 0, height(1.05, 0));
  PaintDot(&texture, dot.x(), dot.y());
  const CameraModel camera = SmallCamera(false);
  VehiclePose pose = Pose(0, 0);
  pose.east_m = 0, pose.north_m = 0, pose.heading_deg = 0;
  // The line of sight to the dot passes under the bump's top.
  const Eigen::Vector3d eye(0, 0, -pose.depth_m);
  const double f = 0.8 / dot.x();
  ASSERT_LT((eye + f * (dot - eye)).z(), height(0.8, 0) - 0.05);
  const cv::Point2d pixel = Project(camera, pose, dot);
  ASSERT_TRUE(pixel.x > 2 && pixel.x < 157);

  FrameRenderer renderer(camera, {});
  renderer.SetTerrain(terrain);
  const cv::Mat frame = renderer.Render(texture, pose, 1);
  const int u = static_cast<int>(std::lround(pixel.x)), v = static_cast<int>(std::lround(pixel.y));
  EXPECT_GT(frame.at<uint8_t>(v, u), 240);  // the bump's white, not the dot
  // Without the bump the dot is there.
  FrameRenderer plain(camera, {});
  plain.SetTerrain(Terrain([](double, double) { return kSeabedUp_m; }));
  EXPECT_LT(plain.Render(texture, pose, 1).at<uint8_t>(v, u), 60);
}

TEST(FrameRendererReliefTest, AFlatTerrainRendersAsThePlane) {
  SeabedTexture texture;
  texture.res_m = 0.004;
  texture.image = MakeProceduralTexture({1000, 1000}, texture.res_m, false, 8, 11);
  texture.east_min = -2;
  texture.north_max = 2;
  const CameraModel camera = SmallCamera(true);
  const VehiclePose pose = Pose(3, 2);
  FrameRenderer plane(camera, {});
  FrameRenderer terrain(camera, {});
  terrain.SetTerrain(Terrain([](double, double) { return kSeabedUp_m; }));
  cv::Mat diff;
  cv::absdiff(plane.Render(texture, pose, 1), terrain.Render(texture, pose, 1), diff);
  EXPECT_LE(cv::mean(diff)[0], 0.05);
  double worst = 0;
  cv::minMaxLoc(diff, nullptr, &worst);
  EXPECT_LE(worst, 2);  // remap's 1/32 px quantisation of slightly different coordinates
}

// The plane path as it was before relief existed: checksums recorded with
// the renderer of commit 2949a05 (golden maps and tests depend on it).
TEST(FrameRendererReliefTest, ThePlanePathIsUnchangedByteForByte) {
  SeabedTexture gray;
  gray.res_m = 0.004;
  gray.image = MakeProceduralTexture({1000, 1000}, gray.res_m, false, 8, 11);
  gray.east_min = -2;
  gray.north_max = 2;
  SeabedTexture colour = gray;
  colour.image = MakeProceduralTexture({1000, 1000}, colour.res_m, true, 8, 12);
  VehiclePose pose = Pose(3, -2);
  pose.altitude_m = 1.8;
  const FrameRenderer clear(SmallCamera(true), {});
  const FrameRenderer degraded(SmallCamera(true), Degradations::Moderate());
  EXPECT_EQ(Fnv1a(clear.Render(gray, pose, 7)), 11844829253751176290ull);
  EXPECT_EQ(Fnv1a(degraded.Render(colour, pose, 7)), 8838175720943980206ull);
}

}  // namespace
}  // namespace seamap
