// Detection rows a hostile or broken writer left (issue 33): each row that
// cannot be a detection is skipped and counted, and the rest is read.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

void Sql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << message;
}

TEST(UnreadableDetections, RowsWithNullOrNonFiniteNumbersOrBrokenJsonAreSkippedAndCounted) {
  testing::TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  {
    MBTilesStore store(path);
    Detection d;
    d.id = 1;
    d.class_name = "crate";
    d.position = {43.1, 131.9};
    d.box = {{43.1, 131.9}, {43.2, 132.0}};
    d.levels = {23};
    d.frames = {4, 5};
    d.seq = 1;
    store.PutDetection(d);
    store.Flush();
  }
  const std::string insert =
      "INSERT INTO detections (id, class, score, lat, lon, seq, box, levels, frames, east_m, "
      "north_m, time_s) VALUES ";
  Sql(path, insert +
                "(2, 'lat null', 0.5, NULL, 131.9, 2, NULL, NULL, NULL, NULL, NULL, NULL),"
                "(3, 'lat inf', 0.5, 9e999, 131.9, 3, NULL, NULL, NULL, NULL, NULL, NULL),"
                "(4, 'lat text', 0.5, 'north', 131.9, 4, NULL, NULL, NULL, NULL, NULL, NULL),"
                "(5, 'score null', NULL, 43.1, 131.9, 5, NULL, NULL, NULL, NULL, NULL, NULL),"
                "(6, 'box null', 0.5, 43.1, 131.9, 6, '[[null,1]]', NULL, NULL, NULL, NULL, NULL),"
                "(7, 'box cut', 0.5, 43.1, 131.9, 7, '[[131.9,', NULL, NULL, NULL, NULL, NULL),"
                "(8, 'levels 1e300', 0.5, 43.1, 131.9, 8, NULL, '[1e300]', NULL, NULL, NULL, NULL),"
                "(9, 'frames text', 0.5, 43.1, 131.9, 9, NULL, NULL, '[\"a\"]', NULL, NULL, NULL),"
                "(10, 'east -inf', 0.5, 43.1, 131.9, 10, NULL, NULL, NULL, -9e999, 1, NULL),"
                "(11, 'time inf', 0.5, 43.1, 131.9, 11, NULL, NULL, NULL, NULL, NULL, 9e999),"
                "(12, 'off the globe', 0.5, 1e300, 131.9, 12, NULL, NULL, NULL, NULL, NULL, NULL),"
                "(13, 'fine', 0.25, -43.1, -179.9, 13, '[[-179.9,-43.1],[-179.8,-43.0]]', '[20]', '[1]', 2.5, -1, "
                "12.5);");
  MBTilesStore reader(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(reader.SkippedDetections(), 0);  // nothing read yet
  const std::vector<Detection> read = reader.Detections();
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].id, 1);
  EXPECT_EQ(read[0].box.size(), 2u);
  EXPECT_EQ(read[0].frames, (std::vector<int>{4, 5}));
  EXPECT_EQ(read[1].id, 13);
  EXPECT_EQ(read[1].levels, std::vector<int>{20});
  ASSERT_TRUE(read[1].position_m);
  EXPECT_EQ((*read[1].position_m)[0], 2.5);
  EXPECT_EQ(reader.SkippedDetections(), 11);
  EXPECT_EQ(reader.Records().SkippedDetections(), 11);
}

}  // namespace
}  // namespace seamap
