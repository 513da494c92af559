// Issue 33, the export rows (the console's row is tests/e2e/hostile_text.e2e.mjs):
// row 12, a GeoTIFF of a map with one frame placed 28 km away, refused with
// its size and the ways out, and no file left when an export is stopped;
// row 14, exporting a map that is still being built or was interrupted,
// refused naming the state unless --partial.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "core/mission/mission_metadata.h"
#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using testing::Seamap;

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("hostile_web", "--frames 12 --line-length 2 --seed 5 --quiet");
}

// The survey built into `map`, with frame `far_frame` moved `far_m` metres east in the navigation (0: none).
void Build(const fs::path& work, const std::string& map, int far_frame, double far_m) {
  const fs::path nav = work / "nav.csv";
  std::ifstream in(Survey().nav);
  std::ofstream out(nav);
  int line = 0;
  for (std::string l; std::getline(in, l); ++line) {
    if (far_m != 0 && line == far_frame + 1) {  // image,time_s,x_m,...
      const size_t x_begin = l.find(',', l.find(',') + 1) + 1, x_end = l.find(',', x_begin);
      l = l.substr(0, x_begin) + std::to_string(std::stod(l.substr(x_begin, x_end - x_begin)) + far_m) +
          l.substr(x_end);
    }
    out << l << "\n";
  }
  out.close();
  std::string log;
  ASSERT_EQ(Seamap("build --images " + Survey().photo + " --nav " + nav.string() + " --camera " + Survey().camera +
                       " --origin " + Survey().origin + " --quiet --out " + map,
                   &log),
            0)
      << log;
}

bool NothingLeft(const std::string& tif) {
  return !fs::exists(tif) && !fs::exists(tif + ".ovr.tmp") && !fs::exists(tif + ".msk.ovr.tmp");
}

TEST(HostileWeb, GeotiffOfAMapWithAFrame28KmAwayIsRefusedWithItsSizeAndTheWayOut) {
  testing::TempDir dir;
  const std::string map = (dir / "far.mbtiles").string(), tif = (dir / "far.tif").string();
  Build(dir.path(), map, 7, 28000);
  std::string log;
  ASSERT_EQ(Seamap("export " + map + " " + tif + " --quiet", &log), 2) << log;
  EXPECT_NE(log.find("seamap export: error: --zoom/--bounds: zoom 25 of " + map + " would be a GeoTIFF of "),
            std::string::npos)
      << log;
  for (const char* said : {"gigapixels", "over 99.99 % is empty", "Choose the area with --bounds W,S,E,N (",
                           "or a coarser --zoom (zoom ", "or pass --allow-sparse to write it anyway"})
    EXPECT_NE(log.find(said), std::string::npos) << said << "\n" << log;
  EXPECT_TRUE(NothingLeft(tif));

  // The bounds it names export the survey: the frames that were not moved, and nothing else.
  const size_t at = log.find("lie within ");
  ASSERT_NE(at, std::string::npos) << log;
  const std::string bounds = log.substr(at + 11, log.find(')', at) - at - 11);
  ASSERT_EQ(Seamap("export " + map + " " + tif + " --quiet --bounds " + bounds, &log), 0) << log;
  EXPECT_TRUE(fs::exists(tif));
  const std::string plain = (dir / "plain.mbtiles").string(), plain_tif = (dir / "plain.tif").string();
  Build(dir.path(), plain, 0, 0);
  std::string reference;
  ASSERT_EQ(Seamap("export " + plain + " " + plain_tif + " --quiet", &reference), 0) << reference;
  // "exported zoom 25 (N tiles, WxH px, ...": within the 12-frame survey's own GeoTIFF, at least half its size.
  auto size_of = [](const std::string& text) {
    int zoom = 0, tiles = 0, w = 0, h = 0;
    const size_t at = text.find("exported zoom");
    if (at != std::string::npos)
      std::sscanf(text.c_str() + at, "exported zoom %d (%d tiles, %dx%d px", &zoom, &tiles, &w, &h);
    return std::vector<int>{zoom, tiles, w, h};
  };
  const std::vector<int> got = size_of(log), survey = size_of(reference);
  EXPECT_EQ(got[0], survey[0]) << log << reference;
  EXPECT_LE(got[2], survey[2]) << log << reference;
  EXPECT_LE(got[3], survey[3]) << log << reference;
  EXPECT_GE(got[2] * got[3] * 2, survey[2] * survey[3]) << log << reference;

  // Bad bounds are named.
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "b.tif").string() + " --bounds 1,2,3", &log), 2);
  EXPECT_NE(log.find("--bounds: expected W,S,E,N in degrees"), std::string::npos) << log;
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "b.tif").string() + " --bounds 10,10,10.001,10.001", &log), 2);
  EXPECT_NE(log.find("--bounds: no tile of"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "b.tif"));
}

TEST(HostileWeb, AGeotiffExportStoppedBySigtermLeavesNoFileBehind) {
  testing::TempDir dir;
  const std::string map = (dir / "far.mbtiles").string(), tif = (dir / "big.tif").string();
  Build(dir.path(), map, 7, 28000);
  testing::ChildProcess export_big({testing::SeamapBinary(), "export", map, tif, "--allow-sparse", "--quiet"},
                                   (dir / "stderr.txt").string());
  // GDAL's temporary overviews appear first: stop it while it writes them.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(tif + ".ovr.tmp") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(tif + ".ovr.tmp"));
  export_big.Signal(SIGTERM);
  const std::optional<int> code = export_big.Wait(std::chrono::seconds(20));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 130);
  std::ifstream err((dir / "stderr.txt").string());
  const std::string said((std::istreambuf_iterator<char>(err)), {});
  EXPECT_NE(said.find("seamap export: stopped; the partial " + tif + " was removed"), std::string::npos) << said;
  EXPECT_TRUE(NothingLeft(tif));
}

// Marks the map as its builder does while it runs.
void RecordState(const std::string& map, const std::string& state) {
  auto store = OpenExistingMap(map, /*writable=*/true);
  store->SetMetadata(kStateKey, state);
  store->Flush();
}

TEST(HostileWeb, ExportingAMapStillBeingBuiltNeedsPartial) {
  testing::TempDir dir;
  const std::string map = (dir / "live.mbtiles").string();
  Build(dir.path(), map, 0, 0);
  RecordState(map, "building");
  std::string log;
  {
    MapLock builder = MapLock::Acquire(map, "--out");  // this process plays the builder
    for (const std::string to : {"tiles", "m.pmtiles", "m.tif"}) {
      const std::string out = (dir / to).string();
      ASSERT_EQ(Seamap("export " + map + " " + out + " --quiet", &log), 2) << to << "\n" << log;
      EXPECT_NE(log.find("seamap export: error: " + map + ": the map is still being built (process " +
                         std::to_string(::getpid()) + " is writing it)"),
                std::string::npos)
          << log;
      EXPECT_NE(log.find("or pass --partial to export what it holds now"), std::string::npos) << log;
      EXPECT_FALSE(fs::exists(out)) << to;
    }
    ASSERT_EQ(Seamap("export " + map + " " + (dir / "d.tif").string() + " --dem", &log), 2) << log;
    EXPECT_NE(log.find("still being built"), std::string::npos) << log;

    ASSERT_EQ(Seamap("export " + map + " " + (dir / "now.pmtiles").string() + " --quiet --partial", &log), 0) << log;
    EXPECT_NE(log.find("seamap export: warning: " + map + " is still being built"), std::string::npos) << log;
    EXPECT_NE(log.find("exporting what it holds now (--partial)"), std::string::npos) << log;
    EXPECT_TRUE(fs::exists(dir / "now.pmtiles"));
  }
  // The builder died: the map is interrupted, and the message says how to go on.
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "tiles").string() + " --quiet", &log), 2) << log;
  EXPECT_NE(log.find(map + ": the map was interrupted: the build stopped without finishing"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "tiles"));
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "tiles").string() + " --quiet --partial", &log), 0) << log;
  EXPECT_NE(log.find("warning: " + map + " was interrupted"), std::string::npos) << log;

  // A replay its operator stopped is a finished map: exported, with a note.
  RecordState(map, "stopped");
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "s.pmtiles").string() + " --quiet", &log), 0) << log;
  EXPECT_NE(log.find("note: " + map + " was stopped by its operator"), std::string::npos) << log;
  RecordState(map, "complete");
  ASSERT_EQ(Seamap("export " + map + " " + (dir / "c.pmtiles").string() + " --quiet", &log), 0) << log;
  EXPECT_EQ(log.find("seamap export: "), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
