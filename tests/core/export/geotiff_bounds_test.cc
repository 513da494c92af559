// Issue 33, row 12: a GeoTIFF of a map with one frame placed far away would
// be a huge, mostly empty raster. It is refused with its size and the ways
// out (--bounds around the main part, a coarser --zoom, --allow-sparse);
// --bounds exports only the tiles touching an area; a stopped or failed
// export leaves no file and no GDAL temporary behind.
#include <filesystem>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "core/export/geotiff_export.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;

constexpr int kZoom = 20, kX0 = 917000, kY0 = 400000, kFarTiles = 40000;

cv::Mat Tile(int k) {
  cv::Mat t(256, 256, CV_8UC2, cv::Scalar(static_cast<double>(k % 256), 255));
  return t;
}

// A 3x2-tile survey at zoom 20 and one tile 40,000 tiles (~30 km) east of it,
// with their zoom 18, 16 and 14 parents.
std::string SparseMap(const testing::TempDir& dir) {
  const std::string path = (dir / "sparse.mbtiles").string();
  auto store = OpenTileStore(path, "png", true);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 3; ++dx) store->PutTile({kZoom, kX0 + dx, kY0 + dy}, EncodeTile(Tile(dx + 3 * dy), {}));
  store->PutTile({kZoom, kX0 + kFarTiles, kY0}, EncodeTile(Tile(7), {}));
  for (int x : {kX0, kX0 + 2, kX0 + kFarTiles}) {
    store->PutTile({kZoom - 2, x / 4, kY0 / 4}, EncodeTile(Tile(9), {}));
    store->PutTile({kZoom - 4, x / 16, kY0 / 16}, EncodeTile(Tile(9), {}));
    store->PutTile({kZoom - 6, x / 64, kY0 / 64}, EncodeTile(Tile(9), {}));
  }
  store->SetMetadata("format", "png");
  store->Flush();
  return path;
}

// Degrees just inside the survey's six tiles.
LatLonBounds SurveyBounds() {
  const LatLonBounds nw = TileBounds({kZoom, kX0, kY0}), se = TileBounds({kZoom, kX0 + 2, kY0 + 1});
  const double inset = 1e-6;
  return {nw.west + inset, se.south + inset, se.east - inset, nw.north - inset};
}

std::string Refusal(const TileStore& map, const std::string& path, const GeotiffOptions& options) {
  try {
    ExportGeotiff(map, "sparse.mbtiles", path, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GeotiffBounds, RefusesAHugeMostlyEmptyRasterWithItsSizeAndTheWaysOut) {
  testing::TempDir dir;
  auto map = OpenExistingMap(SparseMap(dir), false);
  const std::string tif = (dir / "out.tif").string();
  const std::string message = Refusal(*map, tif, {});
  EXPECT_EQ(message.rfind("--zoom/--bounds: zoom 20 of sparse.mbtiles would be a GeoTIFF of 10240256 x 512 px", 0), 0u)
      << message;
  EXPECT_NE(message.find("of which over 99.99 % is empty: 7 of 80002 tiles hold data"), std::string::npos) << message;
  EXPECT_NE(message.find("6 of the 7 tiles, 768 x 512 px, lie within"), std::string::npos) << message;
  // Zooms 18 and 16 (655 and 164 megapixels, as empty) are no way out; zoom 14 (41) is.
  EXPECT_NE(message.find("coarser --zoom (zoom 14: 160256 x 256 px)"), std::string::npos) << message;
  EXPECT_NE(message.find("--allow-sparse"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(tif));
  EXPECT_FALSE(fs::exists(tif + ".ovr.tmp"));

  // The suggested bounds, as printed, export the survey alone.
  const size_t at = message.find("lie within ") + 11;
  GeotiffOptions suggested;
  suggested.bounds = ParseGeotiffBounds(message.substr(at, message.find(')', at) - at));
  const GeotiffSummary s = ExportGeotiff(*map, "sparse.mbtiles", tif, suggested);
  EXPECT_EQ(s.zoom, kZoom);
  EXPECT_EQ(s.tiles, 6);
  EXPECT_EQ(s.width_px, 768);
  EXPECT_EQ(s.height_px, 512);
}

TEST(GeotiffBounds, BoundsKeepTheTilesTouchingThemAtTheChosenZoom) {
  testing::TempDir dir;
  auto map = OpenExistingMap(SparseMap(dir), false);
  GeotiffOptions options;
  options.bounds = SurveyBounds();
  const GeotiffSummary deepest = ExportGeotiff(*map, "sparse.mbtiles", (dir / "a.tif").string(), options);
  EXPECT_EQ(deepest.tiles, 6);
  EXPECT_EQ(deepest.width_px, 3 * 256);
  options.zoom = kZoom - 2;
  const GeotiffSummary coarse = ExportGeotiff(*map, "sparse.mbtiles", (dir / "b.tif").string(), options);
  EXPECT_EQ(coarse.tiles, 1);  // the survey's zoom 18 parent; the far one is outside
  EXPECT_EQ(coarse.width_px, 256);

  GeotiffOptions nowhere;
  nowhere.bounds = LatLonBounds{10, 10, 10.001, 10.001};
  EXPECT_NE(Refusal(*map, (dir / "c.tif").string(), nowhere).find("--bounds: no tile of sparse.mbtiles lies within"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "c.tif"));
}

TEST(GeotiffBounds, AllowSparsePassesTheCheck) {
  testing::TempDir dir;
  auto map = OpenExistingMap(SparseMap(dir), false);
  GeotiffOptions options;
  options.allow_sparse = true;
  // Past the check GDAL starts writing; stopped at its first progress report, it leaves nothing.
  const std::string tif = (dir / "x.tif").string();
  bool started = false;
  EXPECT_THROW(ExportGeotiff(*map, "sparse.mbtiles", tif, options,
                             [&](double) {
                               started = true;
                               throw std::runtime_error("stop");
                             }),
               std::runtime_error);
  EXPECT_TRUE(started);
  EXPECT_FALSE(fs::exists(tif));
  EXPECT_FALSE(fs::exists(tif + ".ovr.tmp"));
}

TEST(GeotiffBounds, ParsesAndChecksBounds) {
  const LatLonBounds b = ParseGeotiffBounds("131.9,43.1, 131.91 ,43.11");
  EXPECT_DOUBLE_EQ(b.west, 131.9);
  EXPECT_DOUBLE_EQ(b.south, 43.1);
  EXPECT_DOUBLE_EQ(b.east, 131.91);
  EXPECT_DOUBLE_EQ(b.north, 43.11);
  for (const std::string bad : {"1,2,3", "1,2,3,4,5", "a,b,c,d", "1,2,3,nan", "1,2,3,4,", "1,2,3,1e999", ""}) {
    try {
      ParseGeotiffBounds(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--bounds: expected W,S,E,N in degrees", 0), 0u) << e.what();
    }
  }
  try {
    ParseGeotiffBounds(std::string(100000, '7'));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
  }
  GeotiffOptions swapped;
  swapped.bounds = LatLonBounds{131.91, 43.1, 131.9, 43.11};
  EXPECT_THROW(swapped.Check(), InputError);
  GeotiffOptions polar;
  polar.bounds = LatLonBounds{0, 80, 1, 89};
  EXPECT_THROW(polar.Check(), InputError);
}

TEST(GeotiffBounds, AStoppedExportLeavesNoFileBehind) {
  testing::TempDir dir;
  auto map = OpenExistingMap(SparseMap(dir), false);
  GeotiffOptions options;
  options.bounds = SurveyBounds();
  const std::string tif = (dir / "stopped.tif").string();
  int calls = 0;
  EXPECT_THROW(ExportGeotiff(*map, "sparse.mbtiles", tif, options,
                             [&](double fraction) {
                               if (++calls > 1 && fraction > 0.2) throw std::runtime_error("Ctrl-C");
                             }),
               std::runtime_error);
  EXPECT_GT(calls, 1);
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find(".tif"), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace seamap
