// The mission's metadata: one reader and one writer for every seamap_* key.
#include "core/mission/mission_metadata.h"

#include <gtest/gtest.h>

#include "core/tiles/mbtiles_store.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(MissionMetadata, ReadsEveryKeyAndNotesTheUnreadableOnes) {
  const MissionMetadata m = ReadMissionMetadata({{"seamap_state", "building"},
                                                 {"seamap_layers", "raw,,enhanced"},
                                                 {"seamap_origin", "43.25,5.5"},
                                                 {"seamap_trajectory", R"({"mode":"refine"})"},
                                                 {"seamap_t0", "1700000000.25"},
                                                 {"seamap_classes", R"(["tyre",3,"crate"])"},
                                                 {"seamap_tile_size", "512"},
                                                 {"seamap_gsd_m", "0.004"},
                                                 {"seamap_channels", "three"},
                                                 {"seamap_frames_used", "12"},
                                                 {"name", "not ours"}});
  EXPECT_EQ(m.state, "building");
  EXPECT_EQ(m.LayersOrRaw(), (std::vector<std::string>{"raw", "enhanced"}));
  EXPECT_EQ(m.ExtraLayers(), (std::vector<std::string>{"enhanced"}));
  ASSERT_TRUE(m.origin);
  EXPECT_EQ(m.origin->lat, 43.25);
  EXPECT_EQ(m.origin->lon, 5.5);
  EXPECT_EQ(m.trajectory->at("mode"), "refine");
  EXPECT_EQ(m.t0, 1700000000.25);
  EXPECT_EQ(m.classes, (std::vector<std::string>{"tyre", "crate"}));
  EXPECT_EQ(m.tile_size_px, 512);
  EXPECT_EQ(m.gsd_m, 0.004);
  EXPECT_FALSE(m.channels);
  EXPECT_EQ(m.unreadable, (std::set<std::string>{"seamap_channels"}));
  EXPECT_EQ(m.frames_used, 12);
  EXPECT_FALSE(m.frames_rejected);
}

TEST(MissionMetadata, AnEmptyMapHasNoMissionAndOneRawLayer) {
  const MissionMetadata m = ReadMissionMetadata(std::map<std::string, std::string>{});
  EXPECT_EQ(m.StateOrEmpty(), "");
  EXPECT_EQ(m.LayersOrRaw(), std::vector<std::string>{"raw"});
  EXPECT_TRUE(m.ExtraLayers().empty());
  EXPECT_FALSE(m.origin);
  try {
    RequireMissionOrigin(m, "m.mbtiles");
    ADD_FAILURE() << "no origin accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "m.mbtiles");
    EXPECT_EQ(e.field(), "seamap_origin");
  }
}

TEST(MissionMetadata, TheWriterWritesOnlyWhatIsSetInTheBuildersFormat) {
  testing::TempDir dir;
  MBTilesStore store((dir / "m.mbtiles").string());
  store.SetMetadata("seamap_state", "complete");
  MissionMetadata m;
  m.origin = LatLon{43.123456789012, -5.5};
  m.gsd_m = 0.0041234567891;
  m.tile_size_px = 256;
  m.layers = std::vector<std::string>{"raw", "enhanced"};
  m.t0 = 1700000000.25;
  m.classes = std::vector<std::string>{"tyre", "crate"};
  m.trajectory = nlohmann::json{{"mode", "filter"}};
  WriteMissionMetadata(&store, m);
  const auto stored = store.Metadata();
  EXPECT_EQ(stored.at("seamap_state"), "complete") << "unset fields are left as stored";
  EXPECT_EQ(stored.at("seamap_origin"), "43.12345679,-5.5");
  EXPECT_EQ(stored.at("seamap_gsd_m"), "0.004123456789");
  EXPECT_EQ(stored.at("seamap_tile_size"), "256");
  EXPECT_EQ(stored.at("seamap_layers"), "raw,enhanced");
  EXPECT_EQ(stored.at("seamap_t0"), "1700000000.25");
  EXPECT_EQ(stored.at("seamap_classes"), R"(["tyre","crate"])");
  EXPECT_EQ(stored.at("seamap_trajectory"), R"({"mode":"filter"})");
  EXPECT_FALSE(stored.count("seamap_channels"));
  const MissionMetadata back = ReadMissionMetadata(store);
  EXPECT_EQ(back.layers, m.layers);
  EXPECT_EQ(back.classes, m.classes);
  EXPECT_EQ(back.t0, m.t0);
  EXPECT_TRUE(back.unreadable.empty());
}

}  // namespace
}  // namespace seamap
