// `seamap build` end to end on a small simulated survey: stores, pyramid,
// GDAL interoperability, metadata, info.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "core/geo/web_mercator.h"
#include "core/mosaic/overview_pyramid.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;
namespace fs = std::filesystem;

const testing::SimulatedSurvey& Survey() {
  return SharedSurvey("build", "--frames 40 --line-length 3 --seed 5");
}

// Every tile of every zoom, decoded.
std::map<TileId, cv::Mat> AllTiles(const TileStore& store, int min_zoom, int max_zoom) {
  std::map<TileId, cv::Mat> tiles;
  auto meta = store.Metadata();
  double w, s, e, n;
  std::sscanf(meta.at("bounds").c_str(), "%lf,%lf,%lf,%lf", &w, &s, &e, &n);
  for (int z = min_zoom; z <= max_zoom; ++z) {
    GlobalPixel nw = LatLonToPixel({n, w}, z, 256), se = LatLonToPixel({s, e}, z, 256);
    for (int ty = static_cast<int>(nw.y / 256) - 1; ty <= static_cast<int>(se.y / 256) + 1; ++ty)
      for (int tx = static_cast<int>(nw.x / 256) - 1; tx <= static_cast<int>(se.x / 256) + 1; ++tx)
        if (auto bytes = store.GetTile({z, tx, ty})) tiles[{z, tx, ty}] = DecodeTile(*bytes);
  }
  return tiles;
}

TEST(Build, MBTilesHasMetadataFramesTrackAndAPyramid) {
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + out, &log), 0) << log;
  EXPECT_NE(log.find("frames used 40, rejected 0"), std::string::npos) << log;

  auto store = OpenTileStore(out, "png", false);
  auto meta = store->Metadata();
  for (const char* key : {"name", "format", "bounds", "center", "minzoom", "maxzoom"})
    EXPECT_TRUE(meta.count(key)) << key;
  EXPECT_EQ(meta["format"], "png");
  EXPECT_EQ(meta["seamap_state"], "complete");
  const int minz = std::stoi(meta["minzoom"]), maxz = std::stoi(meta["maxzoom"]);
  EXPECT_GE(maxz, 24);  // millimetre pixels
  EXPECT_LT(minz, maxz);
  EXPECT_EQ(store->Records().Frames().size(), 40u);
  EXPECT_EQ(store->Records().Track().size(), 40u);

  // Overview tiles exist at every zoom, and the lowest zoom is a single tile
  // or a few (the survey "fits one tile" there).
  auto tiles = AllTiles(*store, minz, maxz);
  std::map<int, int> per_zoom;
  for (const auto& [id, t] : tiles) ++per_zoom[id.z];
  for (int z = minz; z <= maxz; ++z) EXPECT_GT(per_zoom[z], 0) << "zoom " << z;
  EXPECT_LE(per_zoom[minz], 4);
  EXPECT_EQ(static_cast<int64_t>(tiles.size()), store->TileCount());
}

TEST(Build, EveryOverviewTileIsTheReductionOfItsFourChildren) {
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + out, &log), 0) << log;
  auto store = OpenTileStore(out, "png", false);
  auto meta = store->Metadata();
  const int minz = std::stoi(meta["minzoom"]), maxz = std::stoi(meta["maxzoom"]);
  auto tiles = AllTiles(*store, minz, maxz);
  int checked = 0;
  for (const auto& [id, parent] : tiles) {
    if (id.z == maxz) continue;
    cv::Mat mosaic(512, 512, parent.type(), cv::Scalar::all(0));
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        auto it = tiles.find({id.z + 1, 2 * id.x + dx, 2 * id.y + dy});
        if (it != tiles.end()) it->second.copyTo(mosaic(cv::Rect(256 * dx, 256 * dy, 256, 256)));
      }
    cv::Mat expected = ReduceTile2x(mosaic);
    EXPECT_EQ(cv::norm(expected, parent, cv::NORM_INF), 0) << "tile " << id.z << "/" << id.x << "/" << id.y;
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

TEST(Build, FolderOutputMatchesMBTilesTileForTile) {
  testing::TempDir dir;
  const std::string mb = (dir / "m.mbtiles").string(), folder = (dir / "tiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + mb, &log), 0) << log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + folder, &log), 0) << log;
  EXPECT_TRUE(fs::exists(fs::path(folder) / "metadata.json"));
  auto a = OpenTileStore(mb, "png", false);
  auto b = OpenTileStore(folder, "png", false);
  auto meta = a->Metadata();
  auto ta = AllTiles(*a, std::stoi(meta["minzoom"]), std::stoi(meta["maxzoom"]));
  auto tb = AllTiles(*b, std::stoi(meta["minzoom"]), std::stoi(meta["maxzoom"]));
  ASSERT_EQ(ta.size(), tb.size());
  for (const auto& [id, tile] : ta) {
    ASSERT_TRUE(tb.count(id)) << id.z << "/" << id.x << "/" << id.y;
    EXPECT_EQ(cv::norm(tile, tb[id], cv::NORM_INF), 0);
  }
  // Folder layout {z}/{x}/{y}.png
  const TileId first = ta.begin()->first;
  EXPECT_TRUE(fs::exists(fs::path(folder) / std::to_string(first.z) / std::to_string(first.x) /
                         (std::to_string(first.y) + ".png")));
}

TEST(Build, GdalReadsTheMBTiles) {
  std::string version;
  if (testing::RunCommand("gdalinfo --version", &version) != 0) GTEST_SKIP() << "gdalinfo not installed";
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  // GDAL's MBTiles driver stops at zoom 22 (our natural base zoom here is 25).
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --base-zoom 22 --out " + out, &log), 0) << log;
  auto store = OpenTileStore(out, "png", false);
  auto meta = store->Metadata();
  const int minz = std::stoi(meta["minzoom"]), maxz = std::stoi(meta["maxzoom"]);
  store.reset();
  std::string info;
  ASSERT_EQ(testing::RunCommand("gdalinfo " + out, &info), 0) << info;
  EXPECT_NE(info.find("Driver: MBTiles"), std::string::npos) << info;
  EXPECT_NE(info.find("ZOOM_LEVEL=" + std::to_string(maxz)), std::string::npos) << info;
  EXPECT_EQ(maxz, 22);
  // GDAL exposes one overview per zoom below the maximum.
  const size_t overviews_at = info.find("Overviews:");
  if (maxz == minz) {
    EXPECT_EQ(overviews_at, std::string::npos) << info;
  } else {
    ASSERT_NE(overviews_at, std::string::npos) << info;
    const std::string line = info.substr(overviews_at, info.find('\n', overviews_at) - overviews_at);
    EXPECT_EQ(static_cast<int>(std::count(line.begin(), line.end(), ',')) + 1, maxz - minz) << line;
  }
  // Its corner coordinates (EPSG:3857 metres) enclose the survey position.
  const double x = 131.9 * M_PI / 180 * 6378137.0;
  const size_t ul = info.find("Upper Left"), lr = info.find("Lower Right");
  ASSERT_NE(ul, std::string::npos);
  double ulx, uly, lrx, lry;
  ASSERT_EQ(std::sscanf(info.c_str() + info.find('(', ul), "( %lf, %lf", &ulx, &uly), 2);
  ASSERT_EQ(std::sscanf(info.c_str() + info.find('(', lr), "( %lf, %lf", &lrx, &lry), 2);
  // GDAL crops to the metadata bounds, to a pixel of zoom 22 (3.7 cm).
  double w, s, e, n;
  ASSERT_EQ(std::sscanf(meta.at("bounds").c_str(), "%lf,%lf,%lf,%lf", &w, &s, &e, &n), 4);
  auto mercator_x = [](double lon) { return lon * M_PI / 180 * 6378137.0; };
  auto mercator_y = [](double lat) { return std::log(std::tan(M_PI / 4 + lat * M_PI / 360)) * 6378137.0; };
  EXPECT_NEAR(ulx, mercator_x(w), 0.1);
  EXPECT_NEAR(lrx, mercator_x(e), 0.1);
  EXPECT_NEAR(uly, mercator_y(n), 0.1);
  EXPECT_NEAR(lry, mercator_y(s), 0.1);
  EXPECT_LT(std::fabs(ulx - x), 30);  // at the survey origin, 131.9 E
}

TEST(Build, InfoDescribesTheMap) {
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + out, &log), 0) << log;
  ASSERT_EQ(Seamap("info " + out, &log), 0) << log;
  for (const char* word : {"zooms:", "bounds:", "tiles:", "frames:    40 (40 used, 0 rejected)", "size:"})
    EXPECT_NE(log.find(word), std::string::npos) << word << "\n" << log;
}

TEST(Build, ReadsTheShippedSeedFormatNavigationAndOpenCvCamera) {
  // data/ holds hand-written inputs in the seed paper's text format and an
  // OpenCV calibration YAML; any 696x520 frames with those names will do.
  const auto& survey = SharedSurvey("seed_format", "--frames 3 --seed 9");
  const std::string data = std::string(SEAMAP_SOURCE_DIR) + "/data";
  testing::TempDir dir;
  std::string log;
  ASSERT_EQ(Seamap("build --quiet --images " + survey.photo + " --nav " + data + "/seed_format_nav.txt --camera " +
                       data + "/camera_opencv.yaml --origin 43.1,131.9 --out " + (dir / "m.mbtiles").string(),
                   &log),
            0)
      << log;
  EXPECT_NE(log.find("frames used 3, rejected 0"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
