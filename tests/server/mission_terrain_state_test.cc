// The server's view of a mission's height model (MissionState::LoadTerrain,
// TerrainAt): none, then one a build stored, then a replaced one, each
// picked up by a reload; an unreadable one kept as its error until replaced.
#include <cmath>

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/mission/mission_terrain.h"
#include "core/tiles/mbtiles_store.h"
#include "server/api_error.h"
#include "server/mission_state.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

MissionTerrain Flat(float height_m) {
  MissionTerrain t;
  t.origin = {43.0, 5.0};
  t.grid.east0_m = -1;
  t.grid.north0_m = 1;
  t.grid.cell_m = 0.1;
  t.grid.height_m = cv::Mat1f(21, 21, height_m);
  t.grid.sigma_m = cv::Mat1f(21, 21, 0.02f);
  return t;
}

int StatusOf(const MissionState& m, LatLon p) {
  try {
    m.TerrainAt(p);
    return 200;
  } catch (const ApiError& e) {
    return e.status();
  }
}

TEST(MissionTerrainState, ReloadsPickUpAStoredThenAReplacedModel) {
  seamap::testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  const LatLon centre = LocalFrame({43.0, 5.0}).ToLatLon({0, 0});
  MissionState m;
  m.Load(store);
  EXPECT_EQ(StatusOf(m, centre), 404);

  WriteMissionTerrain(&store, Flat(-30));
  m.LoadTerrain(store);
  EXPECT_NEAR(m.TerrainAt(centre).at("height_m").get<double>(), -30, 1e-6);

  WriteMissionTerrain(&store, Flat(-31.5));
  m.Load(store);  // what a followed map's reload does
  EXPECT_NEAR(m.TerrainAt(centre).at("height_m").get<double>(), -31.5, 1e-6);

  TerrainBlob bad = EncodeMissionTerrain(Flat(-32));
  bad.cells.back() ^= 0x5a;
  store.PutTerrain(bad);
  m.LoadTerrain(store);
  EXPECT_EQ(StatusOf(m, centre), 500);

  WriteMissionTerrain(&store, Flat(-33));
  m.LoadTerrain(store);
  EXPECT_NEAR(m.TerrainAt(centre).at("height_m").get<double>(), -33, 1e-6);
}

}  // namespace
}  // namespace seamap::server
