// Who is writing a map: the lock, a second writer refused, the lock released
// by the kernel when its holder is killed (the build state read from it:
// tests/core/mission/build_state_test.cc).
#include "core/tiles/map_lock.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(MapLock, OneWriterAtATimeAndReadersOnlyLook) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  EXPECT_FALSE(MapLock::Holder(map));
  {
    MapLock lock = MapLock::Acquire(map, "--out");
    EXPECT_TRUE(std::filesystem::exists(map + ".lock"));
    ASSERT_TRUE(MapLock::Holder(map));
    EXPECT_EQ(*MapLock::Holder(map), getpid());
    EXPECT_TRUE(MapLock::Holder(map)) << "looking does not take it";
    try {
      MapLock::Acquire(map, "--out");
      ADD_FAILURE() << "a second writer was let in";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--out");
      EXPECT_NE(std::string(e.what()).find("process " + std::to_string(getpid())), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(MapLock::Holder(map));
  EXPECT_FALSE(std::filesystem::exists(map + ".lock")) << "a writer that ends removes its lock file";
  MapLock again = MapLock::Acquire(map, "--out");
  EXPECT_TRUE(again.held());
}

TEST(MapLock, AFolderMapsLockIsBesideIt) {
  EXPECT_EQ(MapLock::LockPath("out/tiles/"), "out/tiles.lock");
  EXPECT_EQ(MapLock::LockPath("m.mbtiles"), "m.mbtiles.lock");
}

}  // namespace
}  // namespace seamap
