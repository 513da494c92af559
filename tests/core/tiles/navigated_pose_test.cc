// The navigation's pose kept beside the corrected one: MBTiles nav_* columns
// (NULL when not corrected), frames.json / track.json fields, and missions
// written before these columns existed (read-only and --append).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/sqlite_columns.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

// The mission tables as SeaMap wrote them before the nav_* columns.
constexpr const char* kOldSchema = R"sql(
CREATE TABLE metadata (name text, value text);
CREATE UNIQUE INDEX metadata_name ON metadata (name);
CREATE TABLE tiles (zoom_level integer, tile_column integer, tile_row integer, tile_data blob);
CREATE UNIQUE INDEX tile_index ON tiles (zoom_level, tile_column, tile_row);
CREATE TABLE frames (id integer primary key, image text, image_path text, time_s real, lat real, lon real,
                     altitude_m real, depth_m real, heading_deg real, pitch_deg real, roll_deg real,
                     footprint text, status text);
CREATE TABLE track (seq integer primary key, time_s real, lat real, lon real, altitude_m real, depth_m real,
                    heading_deg real);
CREATE TABLE detections (id integer primary key, class text, score real, lat real, lon real, note text,
                         source text, frame_id integer, time_s real, created text, updated text, seq integer);
INSERT INTO metadata VALUES ('name', 'old mission');
INSERT INTO tiles VALUES (1, 0, 0, x'00');
INSERT INTO frames VALUES (0, 'a.png', '/p/a.png', 1.5, 43.0, 5.0, 2.0, 30.0, 90.0, 1.0, -1.0,
                           '[[5,43],[5.1,43],[5.1,42.9],[5,42.9]]', 'used');
INSERT INTO frames VALUES (1, 'b.png', '/p/b.png', NULL, 43.1, 5.1, 2.1, 31.0, 91.0, 0.0, 0.0, '', 'too dark');
INSERT INTO track VALUES (0, 1.5, 43.0, 5.0, 2.0, 30.0, 90.0);
INSERT INTO track VALUES (1, NULL, 43.1, 5.1, 2.1, 31.0, 91.0);
)sql";

void WriteOldMission(const std::string& path) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, kOldSchema, nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

std::set<std::string> Columns(const std::string& path, const std::string& table) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  std::set<std::string> out = TableColumns(db, table);
  sqlite3_close(db);
  return out;
}

FrameRecord CorrectedFrame(int id) {
  FrameRecord f;
  f.id = id;
  f.image = "f" + std::to_string(id) + ".png";
  f.position = {43.0 + id * 1e-5, 5.0};
  f.altitude_m = 2;
  f.heading_deg = 10;
  f.status = "used";
  f.nav = NavigatedPose{{43.0 + id * 1e-5 + 2e-6, 5.0 - 3e-6}, 2.25, 31.5, 12.5, 1.25, -0.5};
  return f;
}

TrackPoint CorrectedPoint(int seq) {
  TrackPoint p;
  p.seq = seq;
  p.position = {43.0 + seq * 1e-5, 5.0};
  p.heading_deg = 10;
  p.nav = NavigatedPosition{{43.0 + seq * 1e-5 + 2e-6, 5.0 - 3e-6}, 12.5};
  return p;
}

void ExpectNavEqual(const NavigatedPose& a, const NavigatedPose& b) {
  EXPECT_DOUBLE_EQ(a.position.lat, b.position.lat);
  EXPECT_DOUBLE_EQ(a.position.lon, b.position.lon);
  EXPECT_DOUBLE_EQ(a.altitude_m, b.altitude_m);
  EXPECT_DOUBLE_EQ(a.depth_m, b.depth_m);
  EXPECT_DOUBLE_EQ(a.heading_deg, b.heading_deg);
  EXPECT_DOUBLE_EQ(a.pitch_deg, b.pitch_deg);
  EXPECT_DOUBLE_EQ(a.roll_deg, b.roll_deg);
}

TEST(SqliteColumns, SelectListReadsMissingColumnsAsNull) {
  EXPECT_EQ(SelectList({"a", "c"}, {"a", "b", "c"}), "a, NULL, c");
  EXPECT_EQ(SelectList({}, {"a"}), "NULL");
}

TEST(NavigatedPose, MBTilesKeepsBothPosesAndNullWhenNotCorrected) {
  TempDir dir;
  const std::string path = (dir / "n.mbtiles").string();
  FrameRecord plain = CorrectedFrame(1);
  plain.nav.reset();
  TrackPoint plain_point = CorrectedPoint(1);
  plain_point.nav.reset();
  {
    MBTilesStore store(path);
    store.PutFrame(CorrectedFrame(0));
    store.PutFrame(plain);
    store.PutTrackPoint(CorrectedPoint(0));
    store.PutTrackPoint(plain_point);
  }
  for (const char* column :
       {"nav_lat", "nav_lon", "nav_altitude_m", "nav_depth_m", "nav_heading_deg", "nav_pitch_deg", "nav_roll_deg"})
    EXPECT_TRUE(Columns(path, "frames").count(column)) << column;
  for (const char* column : {"nav_lat", "nav_lon", "nav_heading_deg"})
    EXPECT_TRUE(Columns(path, "track").count(column)) << column;

  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  const auto frames = store.Frames();
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_TRUE(frames[0].nav.has_value());
  ExpectNavEqual(*frames[0].nav, *CorrectedFrame(0).nav);
  EXPECT_DOUBLE_EQ(frames[0].position.lat, CorrectedFrame(0).position.lat);  // the placed pose stays in lat, lon
  EXPECT_FALSE(frames[1].nav.has_value());
  const auto track = store.Track();
  ASSERT_EQ(track.size(), 2u);
  ASSERT_TRUE(track[0].nav.has_value());
  EXPECT_DOUBLE_EQ(track[0].nav->position.lat, CorrectedPoint(0).nav->position.lat);
  EXPECT_DOUBLE_EQ(track[0].nav->position.lon, CorrectedPoint(0).nav->position.lon);
  EXPECT_DOUBLE_EQ(track[0].nav->heading_deg, 12.5);
  EXPECT_FALSE(track[1].nav.has_value());
}

TEST(NavigatedPose, OldMissionReadOnlyReadsEveryFrameAndPoint) {
  TempDir dir;
  const std::string path = (dir / "old.mbtiles").string();
  WriteOldMission(path);
  {
    MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
    const auto frames = store.Frames();
    ASSERT_EQ(frames.size(), 2u);
    EXPECT_EQ(frames[0].image, "a.png");
    EXPECT_DOUBLE_EQ(frames[0].position.lat, 43.0);
    EXPECT_DOUBLE_EQ(frames[0].roll_deg, -1.0);
    EXPECT_DOUBLE_EQ(frames[0].footprint[1].lon, 5.1);
    EXPECT_EQ(frames[1].status, "too dark");
    EXPECT_FALSE(frames[1].time_s.has_value());
    for (const auto& f : frames) EXPECT_FALSE(f.nav.has_value());
    const auto track = store.Track();
    ASSERT_EQ(track.size(), 2u);
    EXPECT_DOUBLE_EQ(track[1].position.lon, 5.1);
    EXPECT_DOUBLE_EQ(track[1].heading_deg, 91.0);
    for (const auto& p : track) EXPECT_FALSE(p.nav.has_value());
    EXPECT_EQ(store.Metadata().at("name"), "old mission");
  }
  EXPECT_FALSE(Columns(path, "frames").count("nav_lat"));  // reading changed nothing
}

TEST(NavigatedPose, OldMissionOpenedToWriteGainsTheColumns) {
  TempDir dir;
  const std::string path = (dir / "old.mbtiles").string();
  WriteOldMission(path);
  {
    MBTilesStore store(path);  // as --append opens it
    store.PutFrame(CorrectedFrame(2));
    store.PutTrackPoint(CorrectedPoint(2));
  }
  const auto frame_columns = Columns(path, "frames");
  for (const char* column :
       {"nav_lat", "nav_lon", "nav_altitude_m", "nav_depth_m", "nav_heading_deg", "nav_pitch_deg", "nav_roll_deg"})
    EXPECT_TRUE(frame_columns.count(column)) << column;
  EXPECT_TRUE(Columns(path, "track").count("nav_heading_deg"));

  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  const auto frames = store.Frames();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_FALSE(frames[0].nav.has_value());  // the old rows: NULL, not corrected
  EXPECT_EQ(frames[1].image, "b.png");
  ASSERT_TRUE(frames[2].nav.has_value());
  ExpectNavEqual(*frames[2].nav, *CorrectedFrame(2).nav);
  const auto track = store.Track();
  ASSERT_EQ(track.size(), 3u);
  EXPECT_FALSE(track[0].nav.has_value());
  ASSERT_TRUE(track[2].nav.has_value());
  EXPECT_DOUBLE_EQ(track[2].nav->heading_deg, 12.5);
  EXPECT_EQ(store.TileCount(), 1);
}

TEST(NavigatedPose, FolderMissionJsonCarriesTheNavFields) {
  TempDir dir;
  const std::string root = (dir / "map").string();
  {
    FolderStore store(root, "png");
    store.PutFrame(CorrectedFrame(0));
    FrameRecord plain = CorrectedFrame(1);
    plain.nav.reset();
    store.PutFrame(plain);
    store.PutTrackPoint(CorrectedPoint(0));
  }
  nlohmann::json frames_json;
  std::ifstream(root + "/frames.json") >> frames_json;
  EXPECT_DOUBLE_EQ(frames_json[0].at("nav_lat").get<double>(), CorrectedFrame(0).nav->position.lat);
  EXPECT_DOUBLE_EQ(frames_json[0].at("nav_roll_deg").get<double>(), -0.5);
  EXPECT_FALSE(frames_json[1].contains("nav_lat"));  // not corrected: as before
  nlohmann::json track_json;
  std::ifstream(root + "/track.json") >> track_json;
  EXPECT_DOUBLE_EQ(track_json[0].at("nav_heading_deg").get<double>(), 12.5);

  FolderStore store(root, "png");
  const auto frames = store.Frames();
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_TRUE(frames[0].nav.has_value());
  ExpectNavEqual(*frames[0].nav, *CorrectedFrame(0).nav);
  EXPECT_FALSE(frames[1].nav.has_value());
  ASSERT_EQ(store.Track().size(), 1u);
  ASSERT_TRUE(store.Track()[0].nav.has_value());
  EXPECT_DOUBLE_EQ(store.Track()[0].nav->position.lon, CorrectedPoint(0).nav->position.lon);
}

}  // namespace
}  // namespace seamap
