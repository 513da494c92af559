#include "core/export/geotiff_export.h"

#include <gdal_priv.h>

#include <cstdio>
#include <memory>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

constexpr double kHalfWorld_m = 20037508.342789244;

// A gray+alpha tile whose pixels say where they are: gray = (x + 3 y + k) % 256,
// alpha 0 on the tile's first row (transparent seabed edge), 255 elsewhere.
cv::Mat GrayTile(int k) {
  cv::Mat t(256, 256, CV_8UC2);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      t.at<cv::Vec2b>(y, x) = {static_cast<uint8_t>((x + 3 * y + k) % 256), static_cast<uint8_t>(y == 0 ? 0 : 255)};
  return t;
}

struct GdalFile {
  explicit GdalFile(const std::string& path) {
    GDALAllRegister();
    ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  }
  std::unique_ptr<GDALDataset> ds;
};

std::vector<uint8_t> ReadBand(GDALDataset* ds, int band, int x, int y, int w, int h) {
  std::vector<uint8_t> px(static_cast<size_t>(w) * h);
  EXPECT_EQ(ds->GetRasterBand(band)->RasterIO(GF_Read, x, y, w, h, px.data(), w, h, GDT_Byte, 0, 0), CE_None);
  return px;
}

// Zoom 23 (beyond GDAL's MBTiles limit of 22): a 3x2-tile extent with one
// tile missing, plus a parent level the export must ignore.
TEST(GeotiffExport, WritesAGeoreferencedCogWhosePixelsAreTheTiles) {
  testing::TempDir dir;
  const std::string map_path = (dir / "m.mbtiles").string();
  const int z = 23, x0 = 7340000, y0 = 3200000;
  {
    auto store = OpenTileStore(map_path, "png", true);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 3; ++dx)
        if (!(dx == 1 && dy == 1)) store->PutTile({z, x0 + dx, y0 + dy}, EncodeTile(GrayTile(dx + 10 * dy), {}));
    store->PutTile({z - 1, x0 / 2, y0 / 2}, EncodeTile(GrayTile(99), {}));
    store->SetMetadata("format", "png");
    store->Flush();
  }
  auto store = OpenExistingMap(map_path, false);
  const std::string tif = (dir / "m.tif").string();
  std::vector<double> progress;
  const GeotiffSummary s = ExportGeotiff(*store, map_path, tif, {}, [&](double f) { progress.push_back(f); });
  EXPECT_EQ(s.zoom, z);
  EXPECT_EQ(s.width_px, 3 * 256);
  EXPECT_EQ(s.height_px, 2 * 256);
  EXPECT_EQ(s.bands, 2);
  EXPECT_EQ(s.tiles, 5);
  ASSERT_FALSE(progress.empty());
  EXPECT_DOUBLE_EQ(progress.back(), 1.0);

  GdalFile f(tif);
  ASSERT_TRUE(f.ds);
  EXPECT_EQ(f.ds->GetRasterXSize(), 768);
  EXPECT_EQ(f.ds->GetRasterYSize(), 512);
  ASSERT_EQ(f.ds->GetRasterCount(), 2);
  EXPECT_EQ(f.ds->GetRasterBand(2)->GetColorInterpretation(), GCI_AlphaBand);
  const char* layout = f.ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
  ASSERT_NE(layout, nullptr);
  EXPECT_STREQ(layout, "COG");
  EXPECT_GE(f.ds->GetRasterBand(1)->GetOverviewCount(), 1);
  const OGRSpatialReference* srs = f.ds->GetSpatialRef();
  ASSERT_NE(srs, nullptr);
  EXPECT_STREQ(srs->GetAuthorityCode(nullptr), "3857");

  // Georeferencing: the corners are the tile grid's, in metres.
  double gt[6];
  ASSERT_EQ(f.ds->GetGeoTransform(gt), CE_None);
  const double tile_m = 2 * kHalfWorld_m / (1 << z);
  EXPECT_NEAR(gt[0], -kHalfWorld_m + x0 * tile_m, 1e-6);
  EXPECT_NEAR(gt[3], kHalfWorld_m - y0 * tile_m, 1e-6);
  EXPECT_NEAR(gt[1], tile_m / 256, 1e-12);
  EXPECT_NEAR(gt[5], -tile_m / 256, 1e-12);

  // Pixels: every tile's, the missing one transparent.
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 3; ++dx) {
      const auto gray = ReadBand(f.ds.get(), 1, dx * 256, dy * 256, 256, 256);
      const auto alpha = ReadBand(f.ds.get(), 2, dx * 256, dy * 256, 256, 256);
      const bool missing = dx == 1 && dy == 1;
      const cv::Mat want = GrayTile(dx + 10 * dy);
      int wrong = 0;
      for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
          const size_t i = static_cast<size_t>(y) * 256 + x;
          const cv::Vec2b w = missing ? cv::Vec2b(0, 0) : want.at<cv::Vec2b>(y, x);
          wrong += gray[i] != w[0] || alpha[i] != w[1];
        }
      EXPECT_EQ(wrong, 0) << "tile " << dx << "," << dy;
    }
}

TEST(GeotiffExport, ColourMapsGiveRgbaAndZoomIsChosen) {
  testing::TempDir dir;
  const std::string map_path = (dir / "c.mbtiles").string();
  cv::Mat bgra(256, 256, CV_8UC4, cv::Scalar(10, 20, 30, 255));  // B, G, R, A
  {
    auto store = OpenTileStore(map_path, "png", true);
    store->PutTile({5, 3, 4}, EncodeTile(bgra, {}));
    store->PutTile({6, 6, 8}, EncodeTile(bgra, {}));
    store->Flush();
  }
  auto store = OpenExistingMap(map_path, false);
  GeotiffOptions options;
  options.zoom = 5;
  const auto s = ExportGeotiff(*store, map_path, (dir / "c.tif").string(), options);
  EXPECT_EQ(s.zoom, 5);
  EXPECT_EQ(s.bands, 4);
  GdalFile f((dir / "c.tif").string());
  ASSERT_TRUE(f.ds);
  EXPECT_EQ(ReadBand(f.ds.get(), 1, 9, 9, 1, 1)[0], 30);  // red
  EXPECT_EQ(ReadBand(f.ds.get(), 2, 9, 9, 1, 1)[0], 20);
  EXPECT_EQ(ReadBand(f.ds.get(), 3, 9, 9, 1, 1)[0], 10);
  EXPECT_EQ(ReadBand(f.ds.get(), 4, 9, 9, 1, 1)[0], 255);
}

TEST(GeotiffExport, NamesBadInput) {
  testing::TempDir dir;
  const std::string map_path = (dir / "e.mbtiles").string();
  { OpenTileStore(map_path, "png", true)->Flush(); }
  auto empty = OpenExistingMap(map_path, false);
  try {
    ExportGeotiff(*empty, map_path, (dir / "e.tif").string(), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no tiles"), std::string::npos) << e.what();
  }
  const std::string one_path = (dir / "one.mbtiles").string();
  {
    auto store = OpenTileStore(one_path, "png", true);
    store->PutTile({4, 1, 1}, EncodeTile(GrayTile(0), {}));
    store->Flush();
  }
  auto map = OpenExistingMap(one_path, false);
  GeotiffOptions z9;
  z9.zoom = 9;
  try {
    ExportGeotiff(*map, map_path, (dir / "e.tif").string(), z9);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no tiles at zoom 9; it has zooms 4..4"), std::string::npos) << e.what();
  }
  try {
    ExportGeotiff(*map, map_path, (dir / "no" / "such" / "e.tif").string(), {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no/such/e.tif"), std::string::npos) << e.what();
  }
  GeotiffOptions bad;
  bad.resampling = "SMOOTH";
  EXPECT_THROW(bad.Check(), InputError);
}

}  // namespace
}  // namespace seamap
