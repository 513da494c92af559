// The height model as a GeoTIFF DEM, read back with GDAL: georeference (a
// cell's centre lands where the local frame puts it), values in the user's
// datum, nodata in holes, overviews.
#include "core/export/dem_export.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

MissionTerrain Terrain(bool depth_datum) {
  MissionTerrain t;
  t.origin = {-33.85, 151.21};  // southern hemisphere, east
  HeightGrid& g = t.grid;
  g.east0_m = -5.0;
  g.north0_m = 12.0;
  g.cell_m = 0.04;
  g.has_depth_datum = depth_datum;
  g.height_m.create(200, 300);
  g.sigma_m = cv::Mat1f(200, 300, 0.01f);
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 300; ++c)
      g.height_m(r, c) = static_cast<float>(-22 + 0.25 * std::sin(0.05 * c) + 0.1 * std::cos(0.07 * r));
  for (int r = 40; r < 50; ++r)
    for (int c = 100; c < 120; ++c) g.height_m(r, c) = NAN;  // a hole
  return t;
}

struct Dem {
  explicit Dem(const std::string& path) {
    GDALAllRegister();
    ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  }
  float At(int row, int col) {
    float v = 0;
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, col, row, 1, 1, &v, 1, 1, GDT_Float32, 0, 0), CE_None);
    return v;
  }
  std::unique_ptr<GDALDataset> ds;
};

TEST(DemExport, HeightsFromTheSeaSurfaceGeoreferencedWithNodataAndOverviews) {
  TempDir dir;
  const std::string path = (dir / "dem.tif").string();
  const MissionTerrain t = Terrain(true);
  const DemSummary s = ExportDem(t, path);
  EXPECT_EQ(s.datum, "sea_surface");
  EXPECT_EQ(s.width_px, 300);
  EXPECT_GE(s.overviews, 2);
  EXPECT_NEAR(s.min_m, -22.35, 0.01);

  Dem dem(path);
  ASSERT_TRUE(dem.ds) << "GDAL cannot open " << path;
  EXPECT_STREQ(dem.ds->GetDriver()->GetDescription(), "GTiff");
  ASSERT_EQ(dem.ds->GetRasterCount(), 1);
  GDALRasterBand* band = dem.ds->GetRasterBand(1);
  EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
  int has_nodata = 0;
  EXPECT_EQ(band->GetNoDataValue(&has_nodata), kDemNodata);
  EXPECT_TRUE(has_nodata);
  EXPECT_EQ(band->GetOverviewCount(), s.overviews);
  EXPECT_STREQ(band->GetUnitType(), "m");
  EXPECT_EQ(dem.At(45, 110), kDemNodata);
  for (const auto& [r, c] : std::vector<std::pair<int, int>>{{0, 0}, {199, 299}, {77, 13}})
    EXPECT_EQ(dem.At(r, c), t.grid.height_m(r, c));
  // An overview averages without the nodata.
  float coarse = 0;
  EXPECT_EQ(band->GetOverview(0)->RasterIO(GF_Read, 10, 10, 1, 1, &coarse, 1, 1, GDT_Float32, 0, 0), CE_None);
  EXPECT_NEAR(coarse, t.grid.height_m(21, 21), 0.02);

  // Georeference: cell (r, c)'s centre through the file's CRS to WGS84.
  double gt[6];
  ASSERT_EQ(dem.ds->GetGeoTransform(gt), CE_None);
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84(
      OGRCreateCoordinateTransformation(dem.ds->GetSpatialRef(), &wgs84));
  ASSERT_TRUE(to_wgs84);
  const LocalFrame frame(t.origin);
  for (const auto& [r, c] : std::vector<std::pair<int, int>>{{0, 0}, {199, 299}, {100, 150}}) {
    double x = gt[0] + (c + 0.5) * gt[1], y = gt[3] + (r + 0.5) * gt[5];
    ASSERT_TRUE(to_wgs84->Transform(1, &x, &y));
    const LatLon want = frame.ToLatLon(t.grid.CellCentre(r, c));
    EXPECT_NEAR(y, want.lat, 1e-9);  // ~0.1 mm
    EXPECT_NEAR(x, want.lon, 1e-9);
  }
}

TEST(DemExport, WithoutDepthHeightsAreRelativeToTheMeanSeabed) {
  TempDir dir;
  const std::string path = (dir / "dem.tif").string();
  const MissionTerrain t = Terrain(false);
  const DemSummary s = ExportDem(t, path);
  EXPECT_EQ(s.datum, "mean_seabed");
  Dem dem(path);
  ASSERT_TRUE(dem.ds);
  double sum = 0;
  int n = 0;
  std::vector<float> all(300 * 200);
  ASSERT_EQ(dem.ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 300, 200, all.data(), 300, 200, GDT_Float32, 0, 0),
            CE_None);
  for (float v : all)
    if (v != kDemNodata) sum += v, ++n;
  EXPECT_NEAR(sum / n, 0, 1e-4);
  EXPECT_NEAR(dem.At(0, 0) - dem.At(77, 13), t.grid.height_m(0, 0) - t.grid.height_m(77, 13), 1e-5);
  EXPECT_STREQ(dem.ds->GetMetadataItem("SEAMAP_HEIGHT_DATUM"), "mean_seabed");
}

TEST(DemExport, AnUnwritablePlaceIsAnErrorNamingIt) {
  TempDir dir;
  const std::string path = (dir / "no_such_folder" / "dem.tif").string();
  try {
    ExportDem(Terrain(true), path);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.tif"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
