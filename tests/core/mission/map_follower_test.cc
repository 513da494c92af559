#include "core/mission/map_follower.h"

#include <gtest/gtest.h>

#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

std::string RecordedState(const TileStore& store) {
  const auto metadata = store.Metadata();
  auto it = metadata.find("seamap_state");
  return it == metadata.end() ? "" : it->second;
}

struct FollowedMap {
  explicit FollowedMap(const std::string& map_path)
      : path(map_path),
        store(OpenTileStore(path, "png", true)),
        follower(path, [this] { return RecordedState(*store); }) {}
  void Record(const std::string& state) {
    store->SetMetadata("seamap_state", state);
    store->Flush();
  }
  std::string path;
  std::unique_ptr<TileStore> store;
  MapFollower follower;
};

TEST(MapFollower, TheFirstStepReportsTheStateAsFoundWithoutAReload) {
  testing::TempDir dir;
  FollowedMap map((dir / "dive.mbtiles").string());
  map.Record("complete");
  const MapFollowStep first = map.follower.Step(*map.store);
  EXPECT_EQ(first.state, "complete");
  EXPECT_TRUE(first.state_changed);
  EXPECT_FALSE(first.reload_records);
  EXPECT_FALSE(first.being_written);
  const MapFollowStep second = map.follower.Step(*map.store);
  EXPECT_FALSE(second.state_changed);
  EXPECT_FALSE(second.reload_records);
}

TEST(MapFollower, AMapBeingBuiltIsReloadedEveryStepAndOnceMoreWhenItEnds) {
  testing::TempDir dir;
  FollowedMap map((dir / "dive.mbtiles").string());
  map.Record("building");
  MapLock lock = MapLock::Acquire(map.path, "--out");  // the builder, as another process would hold it
  EXPECT_TRUE(map.follower.Step(*map.store).being_written);
  MapFollowStep step = map.follower.Step(*map.store);
  EXPECT_EQ(step.state, "building");
  EXPECT_TRUE(step.reload_records);
  EXPECT_FALSE(step.state_changed);
  EXPECT_TRUE(step.being_written);

  map.Record("complete");
  lock = MapLock();
  step = map.follower.Step(*map.store);
  EXPECT_EQ(step.state, "complete");
  EXPECT_TRUE(step.reload_records);  // the last frames and the final state
  EXPECT_TRUE(step.state_changed);
  EXPECT_FALSE(step.being_written);
  step = map.follower.Step(*map.store);
  EXPECT_FALSE(step.reload_records);
  EXPECT_FALSE(step.state_changed);
}

TEST(MapFollower, ABuildWhoseWriterIsGoneIsInterruptedAndSaysHowToGoOn) {
  testing::TempDir dir;
  FollowedMap map((dir / "dive.mbtiles").string());
  map.Record("building");
  const MapFollowStep step = map.follower.Step(*map.store);  // no process holds the lock
  EXPECT_EQ(step.state, "interrupted");
  EXPECT_NE(step.state_detail.find("no process is writing the map"), std::string::npos) << step.state_detail;
  EXPECT_FALSE(step.being_written);
}

TEST(MapFollower, AStoppedReplayOrNoRecordedStateReadsStopped) {
  testing::TempDir dir;
  FollowedMap stopped((dir / "a.mbtiles").string());
  stopped.Record("stopped");
  EXPECT_EQ(stopped.follower.Step(*stopped.store).state, "stopped");
  FollowedMap unknown((dir / "b.mbtiles").string());
  EXPECT_EQ(unknown.follower.Step(*unknown.store).state, "stopped");
  EXPECT_EQ(unknown.follower.Step(*unknown.store).state_detail, "");
}

TEST(MapFollower, AStateChangeOfAMapNobodyBuildsIsNotReported) {
  testing::TempDir dir;
  FollowedMap map((dir / "dive.mbtiles").string());
  map.Record("complete");
  map.follower.Step(*map.store);
  map.Record("stopped");
  const MapFollowStep step = map.follower.Step(*map.store);
  EXPECT_FALSE(step.state_changed);
  EXPECT_FALSE(step.reload_records);
}

}  // namespace
}  // namespace seamap
