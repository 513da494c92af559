// `seamap export MAP dem.tif --dem` on real map files holding a synthetic
// height model, the DEM read back by gdalinfo; the refusals (no model, a
// destination that exists, --dem to something that is not a GeoTIFF); a copy
// of the map to a folder keeps the model and its relief layer.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "core/mission/relief_layer.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::RunCommand;
using testing::Seamap;
using testing::TempDir;
namespace fs = std::filesystem;

// A map with one tile and, when asked, a 6 x 4 m height model at 0.05 m.
std::string WriteMap(const fs::path& dir, bool with_terrain) {
  const std::string path = (dir / (with_terrain ? "dive.mbtiles" : "plain.mbtiles")).string();
  MBTilesStore store(path);
  store.SetMetadata("format", "png");
  store.SetMetadata("minzoom", "20");
  store.SetMetadata("maxzoom", "22");
  store.SetMetadata("seamap_origin", "43.1,131.9");
  store.PutTile({22, 1, 1}, std::vector<uint8_t>{1, 2, 3});
  if (with_terrain) {
    MissionTerrain t;
    t.origin = {43.1, 131.9};
    t.grid.east0_m = -1;
    t.grid.north0_m = 3;
    t.grid.cell_m = 0.05;
    t.grid.height_m.create(80, 120);
    t.grid.sigma_m = cv::Mat1f(80, 120, 0.008f);
    for (int r = 0; r < 80; ++r)
      for (int c = 0; c < 120; ++c)
        t.grid.height_m(r, c) = static_cast<float>(-37.5 + 0.3 * std::sin(0.1 * c) * std::cos(0.08 * r));
    t.grid.height_m(10, 10) = NAN;
    StoreMissionTerrain(&store, t, false);
  }
  store.Flush();
  return path;
}

std::string ReadBinary(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(TerrainExport, DemIsAGeoTiffGdalReadsWithNodataOverviewsAndTheLocalFrame) {
  TempDir dir;
  const std::string map = WriteMap(dir.path(), true), tif = (dir / "dem.tif").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + map + " " + tif + " --dem", &out), 0) << out;
  EXPECT_NE(out.find("120x80 cells"), std::string::npos) << out;
  EXPECT_NE(out.find("sea surface"), std::string::npos) << out;
  ASSERT_EQ(RunCommand("gdalinfo -json " + tif + " 2>&1", &out), 0) << out;
  const nlohmann::json info = nlohmann::json::parse(out);
  EXPECT_EQ(info["size"], nlohmann::json({120, 80}));
  ASSERT_EQ(info["bands"].size(), 1u);
  const nlohmann::json& band = info["bands"][0];
  EXPECT_EQ(band["type"], "Float32");
  EXPECT_EQ(band["noDataValue"], -32767);
  EXPECT_GE(band["overviews"].size(), 1u);
  const std::string wkt = info["coordinateSystem"]["wkt"];
  EXPECT_NE(wkt.find("Transverse Mercator"), std::string::npos) << wkt;
  EXPECT_NE(wkt.find("43.1"), std::string::npos) << wkt;
  EXPECT_NEAR(info["geoTransform"][0].get<double>(), -1.025, 1e-9);  // half a cell west of the first centre
  EXPECT_NEAR(info["geoTransform"][3].get<double>(), 3.025, 1e-9);

  ASSERT_EQ(Seamap("export " + map + " " + tif + " --dem", &out), 2) << out;  // exists
  EXPECT_NE(out.find("--overwrite"), std::string::npos) << out;
  EXPECT_EQ(Seamap("export " + map + " " + tif + " --dem --overwrite", &out), 0) << out;
}

TEST(TerrainExport, AMapWithoutAHeightModelOrABadDestinationIsRefused) {
  TempDir dir;
  const std::string plain = WriteMap(dir.path(), false), map = WriteMap(dir.path(), true);
  std::string out;
  EXPECT_EQ(Seamap("export " + plain + " " + (dir / "dem.tif").string() + " --dem", &out), 2) << out;
  EXPECT_NE(out.find("build it with --terrain"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "dem.tif"));
  EXPECT_EQ(Seamap("export " + map + " " + (dir / "dem.png").string() + " --dem", &out), 2) << out;
  EXPECT_NE(out.find("--dem"), std::string::npos) << out;
}

TEST(TerrainExport, ACopyToAFolderKeepsTheModelAndItsReliefLayer) {
  TempDir dir;
  const std::string map = WriteMap(dir.path(), true), folder = (dir / "tiles").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + map + " " + folder + " --quiet", &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "tiles" / "terrain.json"));
  EXPECT_TRUE(fs::exists(dir / "tiles" / "layers" / "relief" / "metadata.json"));
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "a.tif").string() + " --dem", &out), 0) << out;
  ASSERT_EQ(Seamap("export " + folder + " " + (dir / "b.tif").string() + " --dem", &out), 0) << out;
  EXPECT_EQ(ReadBinary(dir / "a.tif"), ReadBinary(dir / "b.tif"));  // the same model, bit for bit
}

}  // namespace
}  // namespace seamap
