// A survey across the +-180 degree meridian is mapped as one piece: frames
// are placed in global pixels that run on past the world's edge, and the
// tiles there wrap to the other side.
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/mosaic/mosaic_builder.h"
#include "core/mosaic/seabed_projection.h"
#include "core/mosaic/tile_forecast.h"
#include "core/tiles/tile_codec.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(Antimeridian, TileColumnsRunOnPastTheEdgeAndWrap) {
  // Zoom 2: four columns of 256 px, the world 1024 px wide.
  const TileRange across = TilesUnder(2, 256, 1024 - 300, 10, 600, 20);
  EXPECT_EQ(across.x0, 2);
  EXPECT_EQ(across.x1, 5);
  EXPECT_EQ(WrapTileX(2, 4), 0);
  EXPECT_EQ(WrapTileX(2, 5), 1);
  EXPECT_EQ(WrapTileX(2, -1), 3);
  EXPECT_EQ(WrapTileX(2, 3), 3);
  // Each tile at most once, however wide the box; rows stay clipped.
  const TileRange wide = TilesUnder(2, 256, -5000, -100, 100000, 5000);
  EXPECT_EQ(wide.x1 - wide.x0 + 1, 4);
  EXPECT_EQ(wide.y0, 0);
  EXPECT_EQ(wide.y1, 3);
}

TEST(Antimeridian, AFrameAcrossTheMeridianHasASmallContinuousBox) {
  const CameraModel camera = CameraFromFocalLength(8, 12.9, 160, 120);
  const LocalFrame frame({-16.5, 179.99999});  // about a metre west of the meridian
  const SeabedProjection projection(camera, frame, 26, 256);
  const double world = std::ldexp(256.0, 26);
  for (double east : {-2.0, 1.1, 3.0}) {  // west of it, on it, east of it
    VehiclePose pose;
    pose.east_m = east;
    pose.altitude_m = 2;
    const auto outline = projection.Outline(pose);
    ASSERT_TRUE(outline) << east;
    EXPECT_LT(outline->box[2], 2000) << east;  // a frame, not the world
    EXPECT_LT(outline->box[3], 2000) << east;
    EXPECT_NEAR(outline->centre.x, world, 2e4) << east;  // on the origin's side, past the edge when east of it
  }
}

// The same survey, frames of random texture, placed at two origins half a
// world apart: across the antimeridian and across Greenwich. Web Mercator is
// the same there, shifted by half the world's width.
class AntimeridianBuild : public ::testing::Test {
 protected:
  std::unique_ptr<TileStore> Build(LatLon origin, const std::string& name) {
    const CameraModel camera = CameraFromFocalLength(8, 12.9, 160, 120);
    const LocalFrame frame(origin);
    std::vector<FrameSpec> frames;
    cv::RNG rng(7);
    for (int i = 0; i < 12; ++i) {
      FrameSpec f;
      f.index = i;
      f.image = "f" + std::to_string(i) + ".png";
      f.image_path = (dir_ / f.image).string();
      if (!std::filesystem::exists(f.image_path)) {
        cv::Mat image(camera.height, camera.width, CV_8UC1);
        rng.fill(image, cv::RNG::UNIFORM, 20, 230);
        cv::imwrite(f.image_path, image);
      }
      f.pose.east_m = -1.0 + 0.2 * i;  // across the meridian, a metre east of the origin
      f.pose.altitude_m = 2;
      f.pose.heading_deg = 90;
      frames.push_back(f);
    }
    BuildConfig config;
    config.map.base_zoom = 24;
    config.map.min_zoom = 20;
    auto store = OpenTileStore((dir_ / name).string(), "png", true);
    const MosaicPlan plan = PlanMosaic(config.map, camera, frame, frames, 1);
    MosaicBuilder builder(config, camera, frame, plan, store.get());
    builder.Foresee(frames);
    for (const auto& f : frames) builder.Push(f);
    builder.Finish();
    EXPECT_EQ(builder.stats().frames_used, 12);
    return store;
  }
  testing::TempDir dir_;
};

TEST_F(AntimeridianBuild, TilesOnBothSidesMatchTheSameSurveyAtGreenwich) {
  const auto east = Build({-16.5, 179.99999}, "antimeridian.mbtiles");
  const auto green = Build({-16.5, -0.00001}, "greenwich.mbtiles");
  std::map<int, std::pair<int, int>> columns;  // zoom -> lowest, highest column
  for (const TileId& id : east->TileIds()) {
    auto [it, fresh] = columns.emplace(id.z, std::pair{id.x, id.x});
    it->second = {std::min(it->second.first, id.x), std::max(it->second.second, id.x)};
  }
  ASSERT_EQ(columns.count(24), 1u);
  EXPECT_EQ(columns[24].first, 0);               // east of the meridian
  EXPECT_EQ(columns[24].second, (1 << 24) - 1);  // and west of it
  ASSERT_EQ(east->TileCount(), green->TileCount());
  for (const TileId& id : green->TileIds()) {
    const TileId shifted{id.z, (id.x + (1 << (id.z - 1))) % (1 << id.z), id.y};
    const auto a = east->GetTile(shifted);
    ASSERT_TRUE(a) << id.z << "/" << id.x << "/" << id.y;
    cv::Mat diff;
    cv::absdiff(DecodeTile(*a), DecodeTile(*green->GetTile(id)), diff);
    double worst = 0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
    EXPECT_LE(worst, 2) << id.z << "/" << id.x << "/" << id.y;
  }
  // The bounds run on past 180 rather than spanning the world.
  std::string bounds = east->Metadata().at("bounds");
  double w = 0, s = 0, e = 0, n = 0;
  ASSERT_EQ(std::sscanf(bounds.c_str(), "%lf,%lf,%lf,%lf", &w, &s, &e, &n), 4) << bounds;
  EXPECT_GT(e, 180);
  EXPECT_LT(w, 180);
  EXPECT_LT(e - w, 0.001);
}

}  // namespace
}  // namespace seamap
