// GET /api/terrain on a real server on loopback with a real mission file
// holding a synthetic height model: heights in the user's datum at a point,
// 404 with the reason outside the model, in a hole and without one, 400
// naming a bad parameter; the relief layer's tiles and TileJSON; the same
// under a catalogue's /missions/{id}/.
#include <cmath>

#include "core/geo/local_frame.h"
#include "core/mission/mission_terrain.h"
#include "core/mission/relief_layer.h"
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

// 4 x 3 m around the test mission's origin (43, 5): a plane rising east, a hole.
MissionTerrain Plane(bool depth_datum) {
  MissionTerrain t;
  t.origin = {43.0, 5.0};
  HeightGrid& g = t.grid;
  g.east0_m = -2;
  g.north0_m = 1.5;
  g.cell_m = 0.1;
  g.has_depth_datum = depth_datum;
  g.height_m.create(31, 41);
  g.sigma_m.create(31, 41);
  for (int r = 0; r < 31; ++r)
    for (int c = 0; c < 41; ++c) {
      g.height_m(r, c) = static_cast<float>(-31.0 + 0.05 * c);
      g.sigma_m(r, c) = static_cast<float>(0.01 + 0.001 * r);
    }
  g.height_m(20, 30) = NAN;  // a hole at (1.0 east, -0.5 north)
  g.sigma_m(20, 30) = NAN;
  return t;
}

class HttpTerrainTest : public HttpServerTest {
 protected:
  void AddTerrain(bool depth_datum) {
    MBTilesStore store(mission_.path.string());
    StoreMissionTerrain(&store, Plane(depth_datum), false);
  }
  std::string At(LatLon p, const std::string& prefix = "") {
    char q[128];
    std::snprintf(q, sizeof q, "%s/api/terrain?lat=%.9f&lon=%.9f", prefix.c_str(), p.lat, p.lon);
    return q;
  }
  LatLon Local(double east, double north) const { return LocalFrame({43.0, 5.0}).ToLatLon({east, north}); }
};

TEST_F(HttpTerrainTest, AMissionWithoutAHeightModelSaysSo) {
  Start();
  ExpectError(Get(At(Local(0, 0))), 404, "no height model (build it with --terrain)", "no terrain");
  ExpectError(Get("/tiles/relief.json"), 404, "no layer 'relief'", "no relief layer");
}

TEST_F(HttpTerrainTest, AnswersTheHeightAndItsSigmaInTheSeaSurfaceDatum) {
  AddTerrain(true);
  Start();
  const json cell = GetJson(At(Local(0.5, 0.0)));  // cell (15, 25)
  EXPECT_NEAR(cell.at("height_m").get<double>(), -31.0 + 0.05 * 25, 1e-4);
  EXPECT_NEAR(cell.at("sigma_m").get<double>(), 0.01 + 0.001 * 15, 1e-5);
  EXPECT_EQ(cell.at("datum"), "sea_surface");
  EXPECT_NEAR(cell.at("lat").get<double>(), Local(0.5, 0).lat, 1e-9);
  EXPECT_NEAR(cell.at("lon").get<double>(), Local(0.5, 0).lon, 1e-9);
  const json between = GetJson(At(Local(0.55, 0.0)));  // half way to the next cell east
  EXPECT_NEAR(between.at("height_m").get<double>(), -31.0 + 0.05 * 25.5, 1e-4);

  ExpectError(Get(At(Local(1.0, -0.5))), 404, "a hole in the height model", "a hole");
  ExpectError(Get(At(Local(5.0, 0.0))), 404, "outside the height model", "east of it");
  ExpectError(Get("/api/terrain?lon=5"), 400, "parameter 'lat'", "no lat");
  ExpectError(Get("/api/terrain?lat=43&lon=east"), 400, "parameter 'lon'", "a word");
  ExpectError(Get("/api/terrain?lat=91&lon=5"), 400, "parameter 'lat'", "beyond the pole");
  ExpectError(Get("/api/terrain?lat=nan&lon=5"), 400, "parameter 'lat'", "not a number");
}

TEST_F(HttpTerrainTest, WithoutDepthHeightsAreRelativeToTheMeanSeabed) {
  AddTerrain(false);
  Start();
  // Half a cell in from either edge: the plane spans 2 m around its mean.
  const json west = GetJson(At(Local(-1.95, 0.0))), east = GetJson(At(Local(1.95, 0.0)));
  EXPECT_EQ(west.value("datum", ""), "mean_seabed");
  EXPECT_NEAR(west.value("height_m", 0.0), -0.975, 2e-3);
  EXPECT_NEAR(east.value("height_m", 0.0), 0.975, 2e-3);
}

TEST_F(HttpTerrainTest, ServesTheReliefLayerBesideThePhotoLayers) {
  AddTerrain(true);
  Start();
  const json tilejson = GetJson("/tiles.json");
  EXPECT_EQ(tilejson.at("seamap_layers"), json({"raw", "enhanced"}));  // not a photo layer
  const json relief = json::parse(tilejson.at("seamap_relief").get<std::string>());
  EXPECT_NEAR(relief.at("low_m").get<double>(), -31.0, 1e-4);
  EXPECT_NEAR(relief.at("high_m").get<double>(), -29.0, 1e-4);
  const json layer = GetJson("/tiles/relief.json");
  EXPECT_NE(layer.at("tiles")[0].get<std::string>().find("/tiles/relief/{z}/{x}/{y}.png"), std::string::npos);
  MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
  const auto ids = reader.OpenLayer(kReliefLayer)->TileIds();
  ASSERT_FALSE(ids.empty());
  const TileId& id = ids.front();
  auto tile =
      Get("/tiles/relief/" + std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png");
  ASSERT_TRUE(tile);
  EXPECT_EQ(tile->status, 200);
  EXPECT_EQ(tile->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(Text(*reader.OpenLayer(kReliefLayer)->GetTile(id)), tile->body);
}

TEST_F(HttpTerrainTest, AStoredModelThatCannotBeReadIsAnErrorNotACrash) {
  {
    MBTilesStore store(mission_.path.string());
    TerrainBlob blob = EncodeMissionTerrain(Plane(true));
    blob.cells[blob.cells.size() / 3] ^= 0xff;
    store.PutTerrain(blob);
  }
  Start();
  ExpectError(Get(At(Local(0, 0))), 500, "corrupt", "a corrupt model");
  const json status = GetJson("/api/status");  // the rest of the mission is served
  EXPECT_EQ(status.at("name"), "Test mission");
}

TEST_F(HttpTerrainTest, ACatalogueAnswersForEachMission) {
  const test::TestMission maps = test::WriteTestMission(dir_ / "maps");
  {
    MBTilesStore store(maps.path.string());
    StoreMissionTerrain(&store, Plane(true), false);
  }
  HttpServer catalogue(Options(), (dir_ / "maps").string());
  catalogue.Bind();
  catalogue.Start();
  httplib::Client client("127.0.0.1", catalogue.port());
  client.set_read_timeout(60);
  auto res = client.Get(At(Local(0.5, 0.0), "/missions/mission").c_str());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200) << res->body;
  EXPECT_NEAR(json::parse(res->body).at("height_m").get<double>(), -31.0 + 0.05 * 25, 1e-4);
  ExpectError(client.Get(At(Local(9, 9), "/missions/mission").c_str()), 404, "outside the height model", "outside");
  auto relief = client.Get("/missions/mission/tiles/relief.json");
  ASSERT_TRUE(relief);
  EXPECT_EQ(relief->status, 200) << relief->body;
  catalogue.Stop();
}

}  // namespace
}  // namespace seamap::server
