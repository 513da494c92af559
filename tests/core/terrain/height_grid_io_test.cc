#include "core/terrain/height_grid_io.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const LatLon kOrigin{43.1, 131.9};

// A smooth seabed 35 m down, 3 cm cells, with a hole and a per-cell sigma.
HeightGrid Seabed(int rows, int cols) {
  HeightGrid g;
  g.cell_m = 0.03;
  g.east0_m = -1.234;
  g.north0_m = 5.678;
  g.height_m.create(rows, cols);
  g.sigma_m.create(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const LocalXY p = g.CellCentre(r, c);
      g.height_m(r, c) = static_cast<float>(-35 + 0.3 * std::sin(p.east * 1.7) * std::cos(p.north * 1.1));
      g.sigma_m(r, c) = static_cast<float>(0.01 + 0.001 * c);
    }
  g.height_m(3, 4) = NAN;
  g.sigma_m(3, 4) = NAN;
  return g;
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(HeightGridGeotiff, RoundTripInTheLocalFrameIsExact) {
  testing::TempDir dir;
  const std::string path = (dir / "dem.tif").string();
  HeightGrid g = Seabed(300, 400);
  g.has_depth_datum = false;
  HeightGridGeotiffOptions options;
  options.write_sigma = true;
  WriteHeightGridGeotiff(g, kOrigin, path, options);
  const HeightGrid back = ReadHeightGridGeotiff(path, kOrigin);
  ASSERT_EQ(back.height_m.size(), g.height_m.size());
  EXPECT_NEAR(back.east0_m, g.east0_m, 1e-9);
  EXPECT_NEAR(back.north0_m, g.north0_m, 1e-9);
  EXPECT_NEAR(back.cell_m, g.cell_m, 1e-12);
  EXPECT_FALSE(back.has_depth_datum);
  EXPECT_TRUE(std::isnan(back.height_m(3, 4)));
  EXPECT_TRUE(std::isnan(back.sigma_m(3, 4)));
  cv::Mat1f h = g.height_m.clone(), hb = back.height_m.clone();
  h(3, 4) = hb(3, 4) = 0;
  EXPECT_EQ(cv::norm(h, hb, cv::NORM_INF), 0);
  cv::Mat1f s = g.sigma_m.clone(), sb = back.sigma_m.clone();
  s(3, 4) = sb(3, 4) = 0;
  EXPECT_EQ(cv::norm(s, sb, cv::NORM_INF), 0);

  // What GIS tools see: one float32 height band (plus sigma), nodata, a projected CRS, overviews.
  GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->GetRasterCount(), 2);
  GDALRasterBand* band = ds->GetRasterBand(1);
  EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
  int has_nodata = 0;
  EXPECT_EQ(band->GetNoDataValue(&has_nodata), -32767);
  EXPECT_TRUE(has_nodata);
  EXPECT_GE(band->GetOverviewCount(), 1);
  ASSERT_NE(ds->GetSpatialRef(), nullptr);
  EXPECT_TRUE(ds->GetSpatialRef()->IsProjected());
  GDALClose(ds);
}

TEST(HeightGridGeotiff, UtmAndWebMercatorFilesAreReprojectedBack) {
  testing::TempDir dir;
  const HeightGrid g = Seabed(120, 150);
  for (const HeightGridCrs crs : {HeightGridCrs::kUtm, HeightGridCrs::kWebMercator}) {
    const std::string path = (dir / (crs == HeightGridCrs::kUtm ? "utm.tif" : "3857.tif")).string();
    HeightGridGeotiffOptions options;
    options.crs = crs;
    WriteHeightGridGeotiff(g, kOrigin, path, options);
    GDALDataset* ds = GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
    ASSERT_NE(ds, nullptr);
    const char* code = ds->GetSpatialRef()->GetAuthorityCode(nullptr);
    EXPECT_STREQ(code, crs == HeightGridCrs::kUtm ? "32652" : "3857");
    GDALClose(ds);

    const HeightGrid back = ReadHeightGridGeotiff(path, kOrigin);
    ASSERT_FALSE(back.empty());
    // Twice bilinear on a smooth field: millimetres; at the same places.
    int compared = 0;
    double worst = 0;
    for (int r = 10; r < g.rows() - 10; r += 7)
      for (int c = 10; c < g.cols() - 10; c += 7) {
        const LocalXY p = g.CellCentre(r, c);
        double expected = 0, got = 0;
        if (!g.Sample(p, &expected) || !back.Sample(p, &got)) continue;
        worst = std::max(worst, std::fabs(got - expected));
        ++compared;
      }
    EXPECT_GT(compared, 200);
    EXPECT_LT(worst, 0.003);
    EXPECT_NEAR(back.cell_m, g.cell_m, 0.2 * g.cell_m);
  }
}

TEST(HeightGridGeotiff, BadFilesAreRefusedNamingTheFile) {
  testing::TempDir dir;
  const std::string missing = (dir / "missing.tif").string();
  EXPECT_NE(ErrorOf([&] { ReadHeightGridGeotiff(missing, kOrigin); }).find("missing.tif"), std::string::npos);
  // An RGB picture: three bands.
  const std::string rgb = (dir / "photo.png").string();
  cv::imwrite(rgb, cv::Mat(20, 30, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string rgb_error = ErrorOf([&] { ReadHeightGridGeotiff(rgb, kOrigin); });
  EXPECT_NE(rgb_error.find("photo.png"), std::string::npos);
  EXPECT_NE(rgb_error.find("single-band"), std::string::npos);
  // A float TIFF without any georeference.
  const std::string plain = (dir / "plain.tif").string();
  cv::imwrite(plain, cv::Mat1f(20, 30, -35.f));
  const std::string plain_error = ErrorOf([&] { ReadHeightGridGeotiff(plain, kOrigin); });
  EXPECT_NE(plain_error.find("plain.tif"), std::string::npos);
  EXPECT_NE(plain_error.find("coordinate reference system"), std::string::npos);
  // Nothing to write.
  EXPECT_NE(ErrorOf([&] { WriteHeightGridGeotiff(HeightGrid{}, kOrigin, (dir / "empty.tif").string()); }).find("empty"),
            std::string::npos);
}

}  // namespace
}  // namespace seamap
