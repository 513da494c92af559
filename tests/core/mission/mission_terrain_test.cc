// The height model kept in the mission: back bit for bit from both store
// kinds, none where none was stored, and every way a stored one can be wrong
// is an error naming the map.
#include "core/mission/mission_terrain.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

MissionTerrain Terrain(bool depth_datum) {
  MissionTerrain t;
  t.origin = {43.1, 131.9};
  HeightGrid& g = t.grid;
  g.east0_m = -3.125;
  g.north0_m = 7.5;
  g.cell_m = 0.05;
  g.has_depth_datum = depth_datum;
  g.height_m.create(37, 53);
  g.sigma_m.create(37, 53);
  for (int r = 0; r < 37; ++r)
    for (int c = 0; c < 53; ++c) {
      g.height_m(r, c) = static_cast<float>(-35 + 0.3 * std::sin(0.2 * c) * std::cos(0.13 * r) + 1e-7 * r * c);
      g.sigma_m(r, c) = static_cast<float>(0.004 + 0.0001 * c);
    }
  g.height_m(5, 6) = NAN;  // a hole
  g.sigma_m(5, 6) = NAN;
  return t;
}

void ExpectBitIdentical(const cv::Mat1f& a, const cv::Mat1f& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_TRUE(a.isContinuous() && b.isContinuous());
  EXPECT_EQ(std::memcmp(a.ptr(), b.ptr(), a.total() * 4), 0);
}

void ExpectSame(const MissionTerrain& a, const std::optional<MissionTerrain>& b) {
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(a.origin.lat, b->origin.lat);
  EXPECT_EQ(a.origin.lon, b->origin.lon);
  EXPECT_EQ(a.grid.east0_m, b->grid.east0_m);
  EXPECT_EQ(a.grid.north0_m, b->grid.north0_m);
  EXPECT_EQ(a.grid.cell_m, b->grid.cell_m);
  EXPECT_EQ(a.grid.has_depth_datum, b->grid.has_depth_datum);
  ExpectBitIdentical(a.grid.height_m, b->grid.height_m);
  ExpectBitIdentical(a.grid.sigma_m, b->grid.sigma_m);
}

std::string ErrorOf(const TerrainBlob& blob) {
  try {
    DecodeMissionTerrain(blob, "dive.mbtiles");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MissionTerrain, MBTilesReadsBackBitForBit) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  const MissionTerrain t = Terrain(true);
  {
    MBTilesStore store(path);
    EXPECT_FALSE(ReadMissionTerrain(store, path).has_value());
    WriteMissionTerrain(&store, t);
    store.Flush();
  }
  MBTilesStore read(path, MBTilesStore::Mode::kReadOnly);
  ExpectSame(t, ReadMissionTerrain(read, path));
}

TEST(MissionTerrain, FolderReadsBackBitForBitWithoutDepthDatum) {
  TempDir dir;
  const std::string root = (dir / "tiles").string();
  const MissionTerrain t = Terrain(false);
  {
    FolderStore store(root, "png");
    WriteMissionTerrain(&store, t);
  }
  FolderStore read(root, "png", FolderStore::Mode::kReadOnly);
  ExpectSame(t, ReadMissionTerrain(read, root));
}

TEST(MissionTerrain, ABadStoredOneIsAnErrorNamingTheMap) {
  const TerrainBlob good = EncodeMissionTerrain(Terrain(true));
  TerrainBlob flipped = good;
  flipped.cells[flipped.cells.size() / 2] ^= 0x40;
  EXPECT_NE(ErrorOf(flipped).find("corrupt"), std::string::npos) << ErrorOf(flipped);
  EXPECT_NE(ErrorOf(flipped).find("dive.mbtiles"), std::string::npos);
  TerrainBlob cut = good;
  cut.cells.resize(cut.cells.size() - 10);
  EXPECT_NE(ErrorOf(cut).find("cut short"), std::string::npos) << ErrorOf(cut);
  TerrainBlob garbage = good;
  garbage.header_json = "{\"format\": ";
  EXPECT_NE(ErrorOf(garbage).find("unreadable header"), std::string::npos) << ErrorOf(garbage);
  TerrainBlob later = good;
  later.header_json.replace(later.header_json.find("\"version\": 1"), 12, "\"version\": 9");
  EXPECT_NE(ErrorOf(later).find("version 9"), std::string::npos) << ErrorOf(later);
  TerrainBlob huge = good;
  huge.header_json.replace(huge.header_json.find("\"rows\": 37"), 10, "\"rows\": 2000000000");
  EXPECT_NE(ErrorOf(huge).find("impossible size"), std::string::npos) << ErrorOf(huge);
  TerrainBlob missing = good;
  missing.header_json = R"({"format": "seamap-terrain", "version": 1, "encoding": "zlib-float32le"})";
  EXPECT_NE(ErrorOf(missing).find("bad header"), std::string::npos) << ErrorOf(missing);
  // Cells consistent with their checksum but not with the size: a header from another grid.
  TerrainBlob other = EncodeMissionTerrain(Terrain(true));
  other.header_json.replace(other.header_json.find("\"cols\": 53"), 10, "\"cols\": 52");
  EXPECT_NE(ErrorOf(other).find("do not decompress"), std::string::npos) << ErrorOf(other);
}

TEST(MissionTerrain, AGridThatCannotBeKeptIsRefused) {
  MissionTerrain empty;
  EXPECT_THROW(EncodeMissionTerrain(empty), InputError);
  MissionTerrain bad_cell = Terrain(true);
  bad_cell.grid.cell_m = 0;
  EXPECT_THROW(EncodeMissionTerrain(bad_cell), InputError);
  MissionTerrain bad_sigma = Terrain(true);
  bad_sigma.grid.sigma_m = cv::Mat1f(2, 2, 0.f);
  EXPECT_THROW(EncodeMissionTerrain(bad_sigma), InputError);
}

}  // namespace
}  // namespace seamap
