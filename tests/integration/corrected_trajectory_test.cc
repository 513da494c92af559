// A mission's corrected trajectory through the command line: `seamap info`
// says whether it was corrected, and a mission written before the nav_*
// columns existed is still read by every command and can be appended to.
#include <fstream>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;

const testing::SimulatedSurvey& Survey() {
  return SharedSurvey("corrected", "--frames 12 --line-length 2 --seed 11");
}

void Exec(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << sql << ": " << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

// Whether the table has the column, as another reader of the file sees it.
bool HasColumn(const std::string& path, const std::string& table, const std::string& column) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  const std::string sql = "SELECT COUNT(*) FROM pragma_table_info('" + table + "') WHERE name = '" + column + "'";
  sqlite3_stmt* s = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr), SQLITE_OK);
  const bool has = sqlite3_step(s) == SQLITE_ROW && sqlite3_column_int(s, 0) == 1;
  sqlite3_finalize(s);
  sqlite3_close(db);
  return has;
}

TEST(CorrectedTrajectory, InfoSaysWhetherAndHowManyFrames) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + map, &log), 0) << log;
  ASSERT_EQ(Seamap("info " + map, &log), 0) << log;
  EXPECT_NE(log.find("trajectory not corrected"), std::string::npos) << log;

  {  // as a corrected build records it: the navigation's pose beside the placed one
    MBTilesStore store(map);
    for (FrameRecord f : store.Frames()) {
      if (f.id % 3) continue;
      f.nav = NavigatedPose{{f.position.lat + 1e-6, f.position.lon}, f.altitude_m, f.depth_m, f.heading_deg};
      store.PutFrame(f);
    }
  }
  ASSERT_EQ(Seamap("info " + map, &log), 0) << log;
  EXPECT_NE(log.find("trajectory corrected in 4 of 12 frames"), std::string::npos) << log;
}

TEST(CorrectedTrajectory, AMissionWrittenBeforeTheNavColumnsIsReadAndAppendedTo) {
  testing::TempDir dir;
  const std::string map = (dir / "old.mbtiles").string();
  // The first 6 frames now, the other 6 appended (frames in the map already are skipped).
  const std::string first_half = (dir / "first_half.csv").string();
  {
    std::ifstream in(Survey().nav);
    std::ofstream out(first_half);
    std::string line;
    for (int i = 0; i <= 6 && std::getline(in, line); ++i) out << line << "\n";
  }
  const std::string survey_args = Survey().BuildArgs();
  const std::string first_args = survey_args.substr(0, survey_args.find(" --nav ")) + " --nav " + first_half +
                                 survey_args.substr(survey_args.find(" --camera "));
  std::string log;
  ASSERT_EQ(Seamap(first_args + " --out " + map, &log), 0) << log;
  std::string drop;  // back to the schema of the missions made before
  for (const char* c :
       {"nav_lat", "nav_lon", "nav_altitude_m", "nav_depth_m", "nav_heading_deg", "nav_pitch_deg", "nav_roll_deg"})
    drop += std::string("ALTER TABLE frames DROP COLUMN ") + c + ";";
  for (const char* c : {"nav_lat", "nav_lon", "nav_heading_deg"})
    drop += std::string("ALTER TABLE track DROP COLUMN ") + c + ";";
  Exec(map, drop);

  ASSERT_EQ(Seamap("info " + map, &log), 0) << log;  // read-only
  EXPECT_NE(log.find("frames:    6 (6 used, 0 rejected)"), std::string::npos) << log;
  EXPECT_NE(log.find("track:     6 points"), std::string::npos) << log;
  EXPECT_FALSE(HasColumn(map, "frames", "nav_lat")) << "reading changed the file";

  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --append --out " + map, &log), 0) << log;
  EXPECT_TRUE(HasColumn(map, "frames", "nav_roll_deg"));
  EXPECT_TRUE(HasColumn(map, "track", "nav_heading_deg"));
  ASSERT_EQ(Seamap("info " + map, &log), 0) << log;
  EXPECT_NE(log.find("frames:    12 (12 used, 0 rejected)"), std::string::npos) << log;
  EXPECT_NE(log.find("track:     12 points"), std::string::npos) << log;
  MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
  ASSERT_EQ(store.Frames().size(), 12u);
  for (const auto& f : store.Frames()) EXPECT_FALSE(f.nav.has_value()) << f.id;
}

}  // namespace
}  // namespace seamap
