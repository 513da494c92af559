// The maps one server serves: one at the root, or a folder's by id; and maps
// another process is building, followed into live events under one set of rules.
#include "server/mission_registry.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/tiles/map_lock.h"
#include "core/tiles/mbtiles_store.h"
#include "server/api_error.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

int Count(const std::vector<Event>& events, const std::string& type) {
  int n = 0;
  for (const Event& e : events) n += e.type == type;
  return n;
}

// A builder in another process: more frames and track points, then done.
void GrowAndFinish(const std::string& path, int points_before, bool finish) {
  MBTilesStore writer(path, MBTilesStore::Mode::kCreate);
  for (int i = 0; i < 3; ++i) {
    TrackPoint t;
    t.seq = points_before + i;
    t.position = {43.0 + 0.0001 * i, 5.0};
    t.time_s = 200.0 + i;
    writer.PutTrackPoint(t);
  }
  if (finish) writer.SetMetadata("seamap_state", "complete");
  writer.Flush();
}

class MissionRegistryTest : public ::testing::Test {
 protected:
  seamap::testing::TempDir dir_;
};

TEST_F(MissionRegistryTest, OneMapIsAtTheRootAndNoIdNamesIt) {
  test::TestMission m = test::WriteTestMission(dir_.path());
  TileSource tiles(m.path.string(), 2);
  MBTilesStore records(m.path.string(), MBTilesStore::Mode::kReadOnly);
  MissionState mission;
  mission.Load(records);
  EventHub events;
  DetectionRegistry detections(nullptr, &events);
  MissionRegistry registry(&tiles, &mission, &detections, &events, /*token_required=*/true);
  EXPECT_FALSE(registry.catalogue());
  EXPECT_TRUE(registry.Missions().empty());
  EXPECT_EQ(registry.Tiles("").source.get(), &tiles);
  EXPECT_EQ(registry.Tiles("").name, "SeaMap mission");
  EXPECT_EQ(registry.Services("").mission, &mission);
  EXPECT_TRUE(mission.StatusJson()["token_required"].get<bool>());
  try {
    registry.Tiles("mission");
    ADD_FAILURE() << "a mission id on one map";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status(), 404);
  }
  const TileId id = m.tiles.begin()->first;
  const std::string path = std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png";
  auto answer = registry.AnswerMissionTile("", path, std::nullopt);
  ASSERT_TRUE(answer);
  EXPECT_EQ(answer->status, 200);
  EXPECT_FALSE(registry.AnswerMissionTile("mission", path, std::nullopt));  // the backend's 404
}

TEST_F(MissionRegistryTest, AFoldersMapsAreFoundByIdAndUnknownOnesAre404NamingTheFolder) {
  test::TestMission m = test::WriteTestMission(dir_ / "maps");
  MissionRegistry registry((dir_ / "maps").string(), false);
  EXPECT_TRUE(registry.catalogue());
  ASSERT_EQ(registry.Missions().size(), 1u);
  EXPECT_EQ(registry.Missions()[0].id, "mission");
  const MissionTiles tiles = registry.Tiles("mission");
  ASSERT_TRUE(tiles.source);
  EXPECT_EQ(tiles.source.get(), registry.Tiles("mission").source.get());  // made once
  EXPECT_FALSE(tiles.building);
  const MissionServices services = registry.Services("mission");
  EXPECT_EQ(services.mission, registry.Services("mission").mission);  // opened once
  EXPECT_FALSE(services.detections->writable());                      // a catalogue is read-only
  EXPECT_EQ(services.mission->progress().state, "complete");
  try {
    registry.Services("nope");
    ADD_FAILURE() << "an unknown id";
  } catch (const ApiError& e) {
    EXPECT_EQ(e.status(), 404);
    EXPECT_NE(std::string(e.what()).find("no mission 'nope' in " + (dir_ / "maps").string()), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(registry.AnswerMissionTile("", "20/1/2.png", std::nullopt));
  EXPECT_FALSE(registry.AnswerMissionTile("nope", "20/1/2.png", std::nullopt));
}

// The same rules for `serve MAP` and a catalogue's open mission: reloaded
// while a process holds the map's lock, once more when it finishes, then left alone.
TEST_F(MissionRegistryTest, AMapBeingBuiltIsFollowedTheSameWayAtTheRootAndInACatalogue) {
  for (const bool catalogue : {false, true}) {
    SCOPED_TRACE(catalogue ? "catalogue" : "one map");
    seamap::testing::TempDir dir;
    test::TestMission m = test::WriteTestMission(dir / "maps");
    const std::string path = m.path.string();
    {
      MBTilesStore writer(path, MBTilesStore::Mode::kCreate);
      writer.SetMetadata("seamap_state", "building");
      writer.Flush();
    }
    MapLock builder = MapLock::Acquire(path, "--out");

    TileSource tiles(path, 2);
    tiles.SetExternalWriter(true);
    MBTilesStore records(path, MBTilesStore::Mode::kReadOnly);
    MissionState mission;
    mission.Load(records);
    EventHub events;
    DetectionRegistry detections(nullptr, &events);
    std::unique_ptr<MissionRegistry> registry;
    MissionServices services;
    if (catalogue) {
      registry = std::make_unique<MissionRegistry>((dir / "maps").string(), false);
      services = registry->Services("mission");
    } else {
      registry = std::make_unique<MissionRegistry>(&tiles, &mission, &detections, &events, false);
      registry->FollowMap(path, records);
      services = registry->Services("");
    }
    EXPECT_EQ(services.mission->progress().state, "building");
    const int points = services.mission->TrackSize();

    GrowAndFinish(path, points, /*finish=*/false);
    registry->Follow();
    EXPECT_EQ(services.mission->TrackSize(), points + 3);
    auto published = services.events->WaitAfter(0, std::chrono::milliseconds(0));
    EXPECT_EQ(Count(published, "track"), 3);
    EXPECT_EQ(Count(published, "progress"), 1);
    EXPECT_EQ(services.mission->progress().state, "building");

    GrowAndFinish(path, points + 3, /*finish=*/true);
    builder = MapLock();
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // the tile source's metadata is a second old
    registry->Follow();
    EXPECT_EQ(services.mission->progress().state, "complete");
    EXPECT_EQ(services.mission->TrackSize(), points + 6);
    const uint64_t last = services.events->LastId();
    registry->Follow();  // finished: nothing more to tell
    EXPECT_EQ(services.events->LastId(), last);
  }
}

TEST_F(MissionRegistryTest, ABuildNobodyIsWritingAnyMoreSaysItWasInterrupted) {
  test::TestMission m = test::WriteTestMission(dir_ / "maps");
  {
    MBTilesStore writer(m.path.string(), MBTilesStore::Mode::kCreate);
    writer.SetMetadata("seamap_state", "building");
    writer.Flush();
  }
  MissionRegistry registry((dir_ / "maps").string(), false);
  const MissionServices services = registry.Services("mission");
  EXPECT_EQ(services.mission->progress().state, "interrupted");
  EXPECT_NE(services.mission->progress().state_detail.find("no process is writing the map"), std::string::npos);
}

}  // namespace
}  // namespace seamap::server
