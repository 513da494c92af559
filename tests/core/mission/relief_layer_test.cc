// The relief layer drawn from a synthetic height model: tiles where the model
// is, the shaded cell's colour at its place, transparent outside, zooms
// stopping where the cells run out, and the legend's figures recorded.
#include "core/mission/relief_layer.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/mission/mission_metadata.h"
#include "core/terrain/relief_shading.h"
#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_codec.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

MissionTerrain Mound(bool depth_datum) {
  MissionTerrain t;
  t.origin = {43.1, 131.9};
  HeightGrid& g = t.grid;
  g.east0_m = 1.0;
  g.north0_m = 3.0;
  g.cell_m = 0.05;
  g.has_depth_datum = depth_datum;
  g.height_m.create(60, 80);
  g.sigma_m = cv::Mat1f(60, 80, 0.01f);
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 80; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      const double d2 = std::pow(p.east - 3, 2) + std::pow(p.north - 1.5, 2);
      g.height_m(r, c) = static_cast<float>(-36 + 0.6 * std::exp(-d2 / 0.5));
    }
  g.height_m(0, 0) = NAN;
  return t;
}

// The decoded relief pixel at a local point, zoom z.
cv::Vec4b PixelAt(const TileStore& layer, const LocalFrame& frame, LocalXY p, int z) {
  const GlobalPixel px = LatLonToPixel(frame.ToLatLon(p), z, 256);
  const TileId id{z, static_cast<int>(px.x / 256), static_cast<int>(px.y / 256)};
  const auto bytes = layer.GetTile(id);
  if (!bytes) return {0, 0, 0, 0};
  const cv::Mat tile = DecodeTile(*bytes);
  EXPECT_EQ(tile.type(), CV_8UC4);
  return tile.at<cv::Vec4b>(static_cast<int>(px.y) % 256, static_cast<int>(px.x) % 256);
}

TEST(ReliefLayer, DrawsTheShadedModelAtItsPlaceAndRecordsTheLegend) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  const MissionTerrain t = Mound(true);
  MBTilesStore store(path);
  store.SetMetadata("minzoom", "19");
  store.SetMetadata("maxzoom", "26");
  store.SetMetadata("format", "png");
  StoreMissionTerrain(&store, t, false);

  const MissionMetadata m = ReadMissionMetadata(store);
  ASSERT_TRUE(m.relief.has_value());
  EXPECT_EQ((*m.relief)["datum"], "sea_surface");
  EXPECT_NEAR((*m.relief)["low_m"].get<double>(), -36, 0.01);
  EXPECT_NEAR((*m.relief)["high_m"].get<double>(), -35.4, 0.01);
  EXPECT_EQ((*m.relief)["minzoom"], 19);
  EXPECT_EQ((*m.relief)["maxzoom"], 23);  // 1.4 cm pixels at 43 deg: under half a 5 cm cell
  EXPECT_TRUE(ReadMissionTerrain(store, path).has_value());

  auto layer = store.OpenLayer(kReliefLayer);
  EXPECT_EQ(layer->Metadata()["maxzoom"], "23");
  int zoom_24 = 0, zoom_19 = 0;
  for (const TileId& id : layer->TileIds()) {
    zoom_24 += id.z > 23;
    zoom_19 += id.z == 19;
  }
  EXPECT_EQ(zoom_24, 0);
  EXPECT_GE(zoom_19, 1);

  const LocalFrame frame(t.origin);
  const cv::Mat4b shaded = ShadeRelief(t.grid, ReliefStyleFor(t.grid));
  for (const auto& [r, c] : std::vector<std::pair<int, int>>{{30, 40}, {10, 70}, {50, 5}}) {
    const cv::Vec4b got = PixelAt(*layer, frame, t.grid.CellCentre(r, c), 23);
    const cv::Vec4b want = shaded(r, c);
    EXPECT_EQ(got[3], 255);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 10) << "cell " << r << "," << c << " channel " << k;
  }
  // The summit is the ramp's warm end, the foot its cold end.
  const cv::Vec4b top = PixelAt(*layer, frame, {3, 1.5}, 23), foot = PixelAt(*layer, frame, {1.2, 0.2}, 23);
  EXPECT_GT(top[2], top[0]);    // red over blue
  EXPECT_GT(foot[0], foot[2]);  // blue over red
  // Half a metre west of the model: nothing drawn.
  EXPECT_EQ(PixelAt(*layer, frame, {0.5, 1.5}, 19)[3], 0);
}

TEST(ReliefLayer, WithoutDepthTheLegendIsRelativeToTheMeanSeabed) {
  TempDir dir;
  FolderStore store((dir / "tiles").string(), "png");
  const MissionTerrain t = Mound(false);
  ReliefLayerOptions o;
  o.min_zoom = 20;
  o.max_zoom = 21;
  const nlohmann::json relief = WriteReliefLayer(&store, t, o, false);
  EXPECT_EQ(relief["datum"], "mean_seabed");
  EXPECT_LT(relief["low_m"].get<double>(), 0);
  EXPECT_GT(relief["high_m"].get<double>(), 0);
  EXPECT_NEAR(relief["high_m"].get<double>() - relief["low_m"].get<double>(), 0.6, 0.01);
  EXPECT_EQ(relief["maxzoom"], 21);
  EXPECT_GT(relief["tiles"].get<int>(), 0);
  store.Flush();
  FolderStore read((dir / "tiles").string(), "png", FolderStore::Mode::kReadOnly);
  EXPECT_TRUE(ReadMissionMetadata(read).relief.has_value());
  EXPECT_FALSE(read.OpenLayer(kReliefLayer)->TileIds().empty());
}

}  // namespace
}  // namespace seamap
