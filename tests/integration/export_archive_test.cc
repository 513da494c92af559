// `seamap export` to PMTiles and GeoTIFF, read back by independent readers:
// the reference JavaScript PMTiles reader (npm `pmtiles`, in node) and GDAL's
// gdalinfo. Every tile must come back byte-equal to the MBTiles one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/geo/web_mercator.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::RunCommand;
using testing::Seamap;
namespace fs = std::filesystem;

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("export", "--frames 12 --line-length 2 --seed 3");
}

// The survey's map, built once.
const std::string& SurveyMap() {
  static const std::string path = [] {
    const std::string p = Survey().dir + "/map.mbtiles";
    std::string out;
    EXPECT_EQ(Seamap(Survey().BuildArgs() + " --out " + p, &out), 0) << out;
    return p;
  }();
  return path;
}

std::string ReadBinary(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct JsRead {
  nlohmann::json header, metadata;
  std::set<std::string> missing;             // "z x y"
  std::map<std::string, std::string> tiles;  // "z x y" -> bytes
};

std::string Key(const TileId& t) {
  return std::to_string(t.z) + " " + std::to_string(t.x) + " " + std::to_string(t.y);
}

// Reads `ids` from the archive with the npm pmtiles package (in node).
JsRead ReadWithPmtilesJs(const std::string& archive, const std::vector<TileId>& ids, const fs::path& dir) {
  std::ofstream list(dir / "ids.txt");
  for (const auto& t : ids) list << Key(t) << "\n";
  list.close();
  std::string out;
  const int rc = RunCommand("node " + std::string(SEAMAP_SOURCE_DIR) + "/tests/e2e/pmtiles_read.mjs " + archive + " " +
                                (dir / "ids.txt").string() + " " + (dir / "tiles.bin").string(),
                            &out);
  EXPECT_EQ(rc, 0) << out.substr(0, 2000);
  JsRead r;
  std::istringstream lines(out);
  std::string line;
  if (std::getline(lines, line)) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_object()) {
      r.header = j["header"];
      r.metadata = j["metadata"];
    } else {
      ADD_FAILURE() << "reader said: " << out.substr(0, 2000);
    }
  }
  const std::string blob = ReadBinary(dir / "tiles.bin");
  size_t at = 0;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string kind, z, x, y;
    size_t length = 0;
    in >> kind >> z >> x >> y >> length;
    if (kind == "missing") r.missing.insert(z + " " + x + " " + y);
    if (kind != "tile") continue;
    r.tiles[z + " " + x + " " + y] = blob.substr(std::min(at, blob.size()), length);
    at += length;
  }
  EXPECT_EQ(at, blob.size());
  return r;
}

// Every tile of `store` must be in the archive, byte-equal; `absent` tiles must not.
void ExpectSameTiles(const TileStore& store, const std::string& archive, const std::vector<TileId>& absent,
                     const fs::path& dir, JsRead* read = nullptr) {
  std::vector<TileId> ids = store.TileIds();
  const size_t n = ids.size();
  ids.insert(ids.end(), absent.begin(), absent.end());
  JsRead r = ReadWithPmtilesJs(archive, ids, dir);
  size_t equal = 0;
  for (size_t i = 0; i < n; ++i) {
    const auto bytes = store.GetTile(ids[i]);
    const auto got = r.tiles.find(Key(ids[i]));
    equal += bytes && got != r.tiles.end() && got->second == std::string(bytes->begin(), bytes->end());
  }
  EXPECT_EQ(equal, n) << "tiles read back byte-equal";
  EXPECT_EQ(r.tiles.size(), n);
  for (const auto& t : absent) EXPECT_TRUE(r.missing.count(Key(t))) << Key(t) << " should be absent";
  EXPECT_EQ(r.header["numAddressedTiles"].get<int64_t>(), static_cast<int64_t>(n));
  if (read) *read = std::move(r);
}

TEST(ExportArchive, PmtilesOfASurveyReadsBackByteEqualWithTheReferenceReader) {
  testing::TempDir dir;
  const std::string archive = (dir / "survey.pmtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + SurveyMap() + " " + archive, &out), 0) << out;
  EXPECT_NE(out.find("exported"), std::string::npos) << out;
  auto store = OpenExistingMap(SurveyMap(), false);
  const auto ids = store->TileIds();
  ASSERT_GT(ids.size(), 5u);
  TileId deepest = ids.front();
  for (const auto& t : ids)
    if (t.z > deepest.z) deepest = t;
  const std::vector<TileId> absent = {{deepest.z, deepest.x + 50, deepest.y}, {deepest.z + 1, 0, 0}, {0, 0, 0}};
  JsRead r;
  ExpectSameTiles(*store, archive, absent, dir.path(), &r);
  const auto meta = store->Metadata();
  EXPECT_EQ(r.header["tileType"].get<int>(), 2);  // PNG
  EXPECT_EQ(r.header["clustered"].get<bool>(), true);
  EXPECT_EQ(r.header["maxZoom"].get<int>(), deepest.z);
  EXPECT_EQ(r.header["minZoom"].get<int>(), std::stoi(meta.at("minzoom")));
  EXPECT_EQ(r.metadata["name"], meta.at("name"));
  // The dive beside its tiles: the whole track, in order, for a viewer with no SeaMap server.
  const auto track = store->Records().Track();
  const auto& line = r.metadata["seamap_track"]["geometry"]["coordinates"];
  ASSERT_EQ(line.size(), track.size());
  EXPECT_NEAR(line[0][0].get<double>(), track.front().position.lon, 1e-9);
  EXPECT_NEAR(line.back()[1].get<double>(), track.back().position.lat, 1e-9);
  EXPECT_TRUE(r.metadata["seamap_objects"]["features"].is_array());
  // Bounds: the map's, to the header's 1e-7 degrees.
  std::istringstream b(meta.at("bounds"));
  double w, s, e, n;
  char c;
  b >> w >> c >> s >> c >> e >> c >> n;
  EXPECT_NEAR(r.header["minLon"].get<double>(), w, 1e-7);
  EXPECT_NEAR(r.header["maxLat"].get<double>(), n, 1e-7);

  // An existing output is kept unless --overwrite.
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + archive, &out), 0);
  EXPECT_NE(out.find("already exists; use --overwrite"), std::string::npos) << out;
  EXPECT_EQ(Seamap("export " + SurveyMap() + " " + archive + " --overwrite --quiet", &out), 0) << out;
}

// A published archive carries the mission's objects for the viewer: reviewed
// and unreviewed ones with their class, score and status; rejected ones not.
TEST(ExportArchive, PmtilesCarriesTheObjectsButNotTheRejectedOnes) {
  testing::TempDir dir;
  const std::string map = (dir / "objects.mbtiles").string();
  fs::copy_file(SurveyMap(), map);
  {
    auto store = OpenExistingMap(map, true);
    Detection kept;
    kept.id = 1;
    kept.class_name = "tyre";
    kept.score = 0.9;
    kept.position = {43.1, 131.9};
    kept.source = "recogniser";
    kept.status = "confirmed";
    Detection rejected = kept;
    rejected.id = 2;
    rejected.class_name = "rock";
    rejected.status = "rejected";
    store->Records().PutDetection(kept);
    store->Records().PutDetection(rejected);
    store->Flush();
  }
  const std::string archive = (dir / "objects.pmtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + map + " " + archive + " --quiet", &out), 0) << out;
  const JsRead r = ReadWithPmtilesJs(archive, {}, dir.path());
  const auto& features = r.metadata["seamap_objects"]["features"];
  ASSERT_EQ(features.size(), 1u) << r.metadata["seamap_objects"].dump();
  EXPECT_EQ(features[0]["properties"]["class"], "tyre");
  EXPECT_EQ(features[0]["properties"]["status"], "confirmed");
  EXPECT_NEAR(features[0]["geometry"]["coordinates"][0].get<double>(), 131.9, 1e-12);
}

// 8000 scattered tiles of random sizes, a third of them repeats of a few
// blobs: the directory cannot fit the 16 KiB root, so leaves are written.
TEST(ExportArchive, LargeMapsUseLeafDirectoriesAndStoreRepeatsOnce) {
  testing::TempDir dir;
  const std::string map_path = (dir / "big.mbtiles").string();
  std::mt19937 rng(5);
  std::set<std::pair<int, int>> used;
  {
    auto store = OpenTileStore(map_path, "png", true);
    store->SetMetadata("format", "png");
    store->SetMetadata("name", "big");
    std::vector<std::vector<uint8_t>> common(3);
    for (size_t i = 0; i < common.size(); ++i) common[i].assign(40 + i, static_cast<uint8_t>('A' + i));
    while (used.size() < 8000) {
      const int x = rng() % 1024, y = rng() % 1024;
      if (!used.insert({x, y}).second) continue;
      std::vector<uint8_t> bytes(8 + rng() % 400);
      for (auto& v : bytes) v = static_cast<uint8_t>(rng());
      store->PutTile({10, x, y}, rng() % 3 == 0 ? common[rng() % 3] : bytes);
    }
    store->Flush();
  }
  const std::string archive = (dir / "big.pmtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + map_path + " " + archive + " --quiet", &out), 0) << out;
  EXPECT_NE(out.find("leaf directories"), std::string::npos);
  EXPECT_EQ(out.find(" 0 leaf directories"), std::string::npos) << out;
  auto store = OpenExistingMap(map_path, false);
  std::vector<TileId> absent;
  for (int x = 0; absent.size() < 20; ++x)
    if (!used.count({x, 7})) absent.push_back({10, x, 7});
  JsRead r;
  ExpectSameTiles(*store, archive, absent, dir.path(), &r);
  EXPECT_GT(r.header["leafDirectoryLength"].get<int64_t>(), 0);
  EXPECT_LE(r.header["rootDirectoryLength"].get<int64_t>() + 127, 16384);
  EXPECT_LT(r.header["numTileContents"].get<int64_t>(), 8000 * 3 / 4);  // repeats stored once
}

// --layer: the enhanced layer of a two-layer map, alone in the archive and the GeoTIFF.
TEST(ExportArchive, ALayerIsExportedOnItsOwn) {
  testing::TempDir dir;
  const std::string map_path = (dir / "layers.mbtiles").string();
  {
    auto store = OpenTileStore(map_path, "png", true);
    store->SetMetadata("format", "png");
    store->SetMetadata("seamap_layers", "raw,enhanced");
    auto raw = OpenExistingMap(SurveyMap(), false);
    auto enhanced = store->OpenLayer("enhanced");
    int n = 0;
    for (const auto& t : raw->TileIds()) {
      store->PutTile(t, *raw->GetTile(t));
      if (n++ % 2 == 0) enhanced->PutTile(t, *raw->GetTile(t));  // half the tiles, to tell them apart
    }
    enhanced->SetMetadata("name", "enhanced layer");
    enhanced->Flush();
    store->Flush();
  }
  const std::string archive = (dir / "enhanced.pmtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + map_path + " " + archive + " --layer enhanced --quiet", &out), 0) << out;
  auto store = OpenExistingMap(map_path, true);
  auto layer = store->OpenLayer("enhanced");
  ASSERT_LT(layer->TileCount(), store->TileCount());
  JsRead r;
  ExpectSameTiles(*layer, archive, {}, dir.path(), &r);
  EXPECT_EQ(r.metadata["name"], "enhanced layer");
  ASSERT_EQ(Seamap("export " + map_path + " " + (dir / "enhanced.tif").string() + " --layer enhanced --quiet", &out), 0)
      << out;
  EXPECT_NE(out.find("layer enhanced"), std::string::npos) << out;
}

TEST(ExportArchive, GeotiffOfTheDeepestLevelIsGeoreferencedOnTheTileGrid) {
  testing::TempDir dir;
  const std::string tif = (dir / "survey.tif").string();
  std::string out;
  ASSERT_EQ(Seamap("export " + SurveyMap() + " " + tif + " --quiet", &out), 0) << out;
  auto store = OpenExistingMap(SurveyMap(), false);
  int z = 0, x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  for (const auto& t : store->TileIds()) z = std::max(z, t.z);
  for (const auto& t : store->TileIds())
    if (t.z == z) x0 = std::min(x0, t.x), y0 = std::min(y0, t.y), x1 = std::max(x1, t.x), y1 = std::max(y1, t.y);
  ASSERT_EQ(RunCommand("gdalinfo -json " + tif + " 2>&1", &out), 0) << out;
  const auto info = nlohmann::json::parse(out, nullptr, false);
  ASSERT_TRUE(info.is_object()) << out;
  EXPECT_EQ(info["size"][0].get<int>(), (x1 - x0 + 1) * 256);
  EXPECT_EQ(info["size"][1].get<int>(), (y1 - y0 + 1) * 256);
  EXPECT_EQ(info["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG");
  EXPECT_NE(info["coordinateSystem"]["wkt"].get<std::string>().find("\"EPSG\",3857"), std::string::npos);
  EXPECT_FALSE(info["bands"][0]["overviews"].empty());
  // The geotransform is the tile grid's, in metres; the corners in degrees too
  // (gdalinfo's own reprojection, printed to 1e-7 degrees).
  const double half_world_m = 20037508.342789244, tile_m = 2 * half_world_m / (1 << z);
  const auto& gt = info["geoTransform"];
  EXPECT_NEAR(gt[0].get<double>(), -half_world_m + x0 * tile_m, 1e-6);
  EXPECT_NEAR(gt[3].get<double>(), half_world_m - y0 * tile_m, 1e-6);
  EXPECT_NEAR(gt[1].get<double>(), tile_m / 256, 1e-12);
  EXPECT_NEAR(gt[5].get<double>(), -tile_m / 256, 1e-12);
  const LatLonBounds nw = TileBounds({z, x0, y0}), se = TileBounds({z, x1, y1});
  double west = 180, east = -180, south = 90, north = -90;
  for (const auto& p : info["wgs84Extent"]["coordinates"][0]) {
    west = std::min(west, p[0].get<double>());
    east = std::max(east, p[0].get<double>());
    south = std::min(south, p[1].get<double>());
    north = std::max(north, p[1].get<double>());
  }
  EXPECT_NEAR(west, nw.west, 1e-7);
  EXPECT_NEAR(north, nw.north, 1e-7);
  EXPECT_NEAR(east, se.east, 1e-7);
  EXPECT_NEAR(south, se.south, 1e-7);
}

TEST(ExportArchive, BadInputIsNamed) {
  testing::TempDir dir;
  std::string out;
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + (dir / "no/such/m.pmtiles").string(), &out), 0);
  EXPECT_NE(out.find("no/such/m.pmtiles"), std::string::npos) << out;
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + (dir / "no/such/m.tif").string(), &out), 0);
  EXPECT_NE(out.find("no/such/m.tif"), std::string::npos) << out;
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + (dir / "m.tif").string() + " --zoom 3", &out), 0);
  EXPECT_NE(out.find("--zoom: the map"), std::string::npos) << out;
  EXPECT_NE(out.find("has no tiles at zoom 3"), std::string::npos) << out;
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + (dir / "m.pmtiles").string() + " --layer nope", &out), 0);
  EXPECT_NE(out.find("'nope' is not an extra layer"), std::string::npos) << out;
  EXPECT_NE(Seamap("export " + SurveyMap() + " " + (dir / "m.pmtiles").string() + " --zoom 3", &out), 0);
  EXPECT_NE(out.find("--zoom"), std::string::npos) << out;  // GeoTIFF-only option
  const std::string empty = (dir / "empty.mbtiles").string();
  OpenTileStore(empty, "png", true)->Flush();
  EXPECT_NE(Seamap("export " + empty + " " + (dir / "e.pmtiles").string(), &out), 0);
  EXPECT_NE(out.find("no tiles to export"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "e.pmtiles"));
  EXPECT_FALSE(fs::exists(dir / "e.pmtiles.tiles.tmp"));
}

}  // namespace
}  // namespace seamap
