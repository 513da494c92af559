// A seabed texture longer than cv::remap takes (32,767 px a side: a
// 20,000-frame survey's) renders frames as the same seabed cut to a texture
// under the limit does: up to the texture coordinates' float rounding, which
// is coarser 38,000 px from the texture's edge than 1,000 px from it.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "core/sim/frame_renderer.h"
#include "core/sim/seabed_texture.h"

namespace seamap {
namespace {

CameraModel SmallCamera() {
  CameraModel c;
  c.width = 160;
  c.height = 120;
  c.fx = c.fy = 140;
  c.cx = 80;
  c.cy = 60;
  return c;
}

TEST(LargeTextureRender, AFrameFromATextureOverTheRemapLimitIsTheFrameFromItsPart) {
  // 40,000 x 400 px at 10 mm (400 m x 4 m): random grey, so any shift or
  // wrong neighbour shows.
  SeabedTexture whole;
  whole.res_m = 0.01;
  whole.image.create(400, 40000, CV_8UC1);
  cv::RNG rng(29);
  rng.fill(whole.image, cv::RNG::UNIFORM, 0, 256);
  whole.east_min = -200;
  whole.north_max = 2;
  // The last 3,000 columns alone (the frames below see only them), under the limit.
  SeabedTexture part = whole;
  part.image = whole.image.colRange(37000, 40000).clone();
  part.east_min = whole.east_min + 37000 * whole.res_m;

  const FrameRenderer renderer(SmallCamera(), Degradations{});
  for (double east : {181.234, 196.5, 199.9}) {  // within the part; the last at the texture's east edge
    VehiclePose pose;
    pose.east_m = east;
    pose.north_m = -0.117;
    pose.altitude_m = 1.8;
    pose.heading_deg = 30;
    pose.pitch_deg = 2;
    const cv::Mat from_whole = renderer.Render(whole, pose, 1), from_part = renderer.Render(part, pose, 1);
    ASSERT_EQ(from_whole.size(), from_part.size());
    // remap interpolates at 1/32 px: a coordinate rounded to the next step
    // moves a sample by at most 255/32 grey levels; a pixel's shift would move
    // them by ~85 on average.
    EXPECT_LE(cv::norm(from_whole, from_part, cv::NORM_INF), 8) << east;
    EXPECT_LT(cv::norm(from_whole, from_part, cv::NORM_L1) / from_whole.total(), 0.5) << east;
    EXPECT_GT(cv::countNonZero(from_whole), 160 * 120 / 3) << east;  // the seabed was seen
  }
  // A frame over no texture at all is black, not an error.
  VehiclePose far;
  far.east_m = 500;
  far.altitude_m = 1.8;
  EXPECT_EQ(cv::countNonZero(renderer.Render(whole, far, 1)), 0);
}

}  // namespace
}  // namespace seamap
