// The mission's class table (append-only) and t0, kept in the metadata.
#include "core/mission/mission_classes.h"

#include <gtest/gtest.h>

#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(MissionClasses, TheTableOnlyGrowsAndIdsKeepTheirMeaning) {
  std::vector<std::string> table;
  EXPECT_TRUE(ExtendClassTable(&table, {"tyre", "crate", "pipe"}));
  EXPECT_FALSE(ExtendClassTable(&table, {"crate", "tyre", ""}));
  EXPECT_TRUE(ExtendClassTable(&table, {"wreck", "tyre"}));
  EXPECT_EQ(table, (std::vector<std::string>{"tyre", "crate", "pipe", "wreck"}));
  EXPECT_EQ(ClassId(table, "pipe"), 2);
  EXPECT_EQ(ClassId(table, "rock"), 255);
  for (int i = 0; i < 300; ++i) table.push_back("c" + std::to_string(i));
  EXPECT_EQ(ClassId(table, "c250"), 254);
  EXPECT_EQ(ClassId(table, "c251"), 255);  // beyond the record's 8 bits
}

TEST(MissionClasses, StoredInTheMetadataAndExtendedByOlderDetections) {
  testing::TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  {
    MBTilesStore store(path);
    Detection d;
    d.id = 1;
    d.class_name = "wreck";
    store.PutDetection(d);
    StoreClassTable(&store, {"tyre", "crate"});
    FrameRecord f;
    f.id = 0;  // no time: the next frame's time is t0
    store.PutFrame(f);
    f.id = 1;
    f.time_s = 1700000000.25;
    store.PutFrame(f);
    f.id = 2;
    f.time_s = 1700000000.05;  // earlier, but a later frame
    store.PutFrame(f);
    EXPECT_EQ(StoreMissionT0(&store), 1700000000.25);
    store.Flush();
  }
  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(MissionClassTable(store), (std::vector<std::string>{"tyre", "crate", "wreck"}));
  EXPECT_EQ(store.Metadata().at(kT0Key), "1700000000.25");
  EXPECT_EQ(MissionT0(store), 1700000000.25);
}

}  // namespace
}  // namespace seamap
