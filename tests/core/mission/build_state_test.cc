// The build state `seamap info` and `seamap serve` tell: recorded, held by a
// live builder, or interrupted (the builder was killed with its lock held).
#include "core/mission/build_state.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "core/tiles/map_lock.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(MapLock, KillNineReleasesTheLockAndTheMapReadsAsInterrupted) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  {
    MBTilesStore store(map);
    store.SetMetadata("seamap_state", "building");
    CheckpointUpdate u;
    u.progress = R"({"frame_index": 41, "frames_total": 150})";
    store.WriteCheckpoint(u);
  }
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  if (child == 0) {  // a "build" that holds the lock until it is killed
    MapLock lock = MapLock::Acquire(map, "--out");
    (void)!write(ready[1], "x", 1);
    pause();
    _exit(0);
  }
  char c;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  MBTilesStore reader(map, MBTilesStore::Mode::kReadOnly);
  MapBuildState live = ReadBuildState(map, reader);
  EXPECT_EQ(live.state, "building");
  ASSERT_TRUE(live.writer_pid);
  EXPECT_EQ(*live.writer_pid, child);

  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  EXPECT_TRUE(std::filesystem::exists(map + ".lock")) << "nobody removed it";
  MapBuildState dead = ReadBuildState(map, reader);
  EXPECT_EQ(dead.state, "interrupted");
  EXPECT_TRUE(dead.checkpoint);
  EXPECT_EQ(dead.frames_done, 42);
  EXPECT_NE(dead.Explanation().find("--resume"), std::string::npos) << dead.Explanation();
  EXPECT_NE(dead.Explanation().find("42 of 150"), std::string::npos) << dead.Explanation();
  MapLock taken = MapLock::Acquire(map, "--out");  // the stale file is taken over
  EXPECT_TRUE(taken.held());
  close(ready[0]);
  close(ready[1]);
}

TEST(MapBuildState, CompleteAndUnbuiltMapsAreWhatTheySay) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  MBTilesStore store(map);
  EXPECT_EQ(ReadBuildState(map, store).state, "");
  store.SetMetadata("seamap_state", "complete");
  EXPECT_EQ(ReadBuildState(map, store).state, "complete");
  EXPECT_EQ(ReadBuildState(map, store).Explanation(), "");
  store.SetMetadata("seamap_state", "building");  // no checkpoint: a replay's
  const MapBuildState s = ReadBuildState(map, store);
  EXPECT_EQ(s.state, "interrupted");
  EXPECT_NE(s.Explanation().find("--append"), std::string::npos) << s.Explanation();
}

}  // namespace
}  // namespace seamap
