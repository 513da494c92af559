#include "core/tiles/mbtiles_store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <thread>

#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::RunCommand;
using testing::TempDir;

// A second, independent connection, as another process would see the file.
class RawDb {
 public:
  explicit RawDb(const std::string& path) {
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  }
  ~RawDb() { sqlite3_close(db_); }
  // First column of the first row as text ("" when no row).
  std::string Query(const std::string& sql) {
    sqlite3_stmt* s = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr), SQLITE_OK) << sql;
    std::string out;
    if (sqlite3_step(s) == SQLITE_ROW && sqlite3_column_text(s, 0))
      out = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
    return out;
  }

 private:
  sqlite3* db_ = nullptr;
};

std::vector<uint8_t> Bytes(const std::string& text) {
  return {text.begin(), text.end()};
}

FrameRecord SampleFrame(int id) {
  FrameRecord f;
  f.id = id;
  f.image = "img_" + std::to_string(id) + ".jpg";
  f.image_path = "/data/photos/img_" + std::to_string(id) + ".jpg";
  f.time_s = 1000.5 + id;
  f.position = {43.25 + id * 1e-5, 5.125};
  f.altitude_m = 2.5;
  f.depth_m = 40.25;
  f.heading_deg = 91;
  f.pitch_deg = -1.5;
  f.roll_deg = 0.75;
  f.footprint = {LatLon{43.1, 5.1}, LatLon{43.1, 5.2}, LatLon{43.0, 5.2}, LatLon{43.0, 5.1}};
  f.status = id % 2 ? "used" : "too dark";
  return f;
}

TEST(MBTilesStore, PutGetAndReplace) {
  TempDir dir;
  MBTilesStore store((dir / "a.mbtiles").string());
  EXPECT_FALSE(store.GetTile({5, 3, 4}).has_value());
  store.PutTile({5, 3, 4}, Bytes("first"));
  store.PutTile({5, 3, 5}, Bytes("other"));
  store.PutTile({5, 3, 4}, Bytes("second"));
  ASSERT_TRUE(store.GetTile({5, 3, 4}).has_value());  // visible before Flush
  EXPECT_EQ(*store.GetTile({5, 3, 4}), Bytes("second"));
  EXPECT_EQ(*store.GetTile({5, 3, 5}), Bytes("other"));
  EXPECT_EQ(store.TileCount(), 2);
}

TEST(MBTilesStore, StoresRowsInTmsNumbering) {
  TempDir dir;
  const std::string path = (dir / "tms.mbtiles").string();
  {
    MBTilesStore store(path);
    store.PutTile({3, 2, 1}, Bytes("tile"));  // XYZ row 1 at z=3 is TMS row 8-1-1 = 6
  }
  RawDb raw(path);
  EXPECT_EQ(raw.Query("SELECT tile_row FROM tiles WHERE zoom_level=3 AND tile_column=2"), "6");
  EXPECT_EQ(raw.Query("SELECT CAST(tile_data AS TEXT) FROM tiles WHERE tile_row=6"), "tile");
}

TEST(MBTilesStore, SchemaAndWalMode) {
  TempDir dir;
  const std::string path = (dir / "s.mbtiles").string();
  MBTilesStore store(path);
  store.Flush();
  RawDb raw(path);
  EXPECT_EQ(raw.Query("PRAGMA journal_mode"), "wal");
  for (const char* table : {"metadata", "tiles", "frames", "track"})
    EXPECT_EQ(raw.Query(std::string("SELECT name FROM sqlite_master WHERE type='table' AND name='") + table + "'"),
              table);
  EXPECT_EQ(raw.Query("SELECT sql FROM sqlite_master WHERE name='tile_index'"),
            "CREATE UNIQUE INDEX tile_index ON tiles (zoom_level, tile_column, tile_row)");
}

TEST(MBTilesStore, MetadataRoundTripAndReplace) {
  TempDir dir;
  const std::string path = (dir / "m.mbtiles").string();
  {
    MBTilesStore store(path);
    store.SetMetadata("name", "dive 1");
    store.SetMetadata("format", "png");
    store.SetMetadata("name", "dive 2");
    const auto meta = store.Metadata();
    EXPECT_EQ(meta.size(), 2u);
    EXPECT_EQ(meta.at("name"), "dive 2");
  }
  RawDb raw(path);
  EXPECT_EQ(raw.Query("SELECT value FROM metadata WHERE name='format'"), "png");
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM metadata WHERE name='name'"), "1");
}

TEST(MBTilesStore, FramesAndTrackRoundTrip) {
  TempDir dir;
  const std::string path = (dir / "f.mbtiles").string();
  {
    MBTilesStore store(path);
    store.PutFrame(SampleFrame(2));
    store.PutFrame(SampleFrame(1));
    FrameRecord replaced = SampleFrame(2);
    replaced.status = "blurred";
    replaced.time_s.reset();
    store.PutFrame(replaced);
    store.PutTrackPoint({1, 5.0, {43.0, 5.0}, 3.0, 41.0, 90.0, std::nullopt});
    store.PutTrackPoint({0, std::nullopt, {43.1, 5.1}, 2.0, 40.0, 80.0, std::nullopt});
  }
  MBTilesStore store(path);  // reopened: what was written survived
  const auto frames = store.Frames();
  ASSERT_EQ(frames.size(), 2u);
  const FrameRecord expect = SampleFrame(1);
  EXPECT_EQ(frames[0].id, 1);
  EXPECT_EQ(frames[0].image, expect.image);
  EXPECT_EQ(frames[0].image_path, expect.image_path);
  EXPECT_EQ(frames[0].time_s, expect.time_s);
  EXPECT_DOUBLE_EQ(frames[0].position.lat, expect.position.lat);
  EXPECT_DOUBLE_EQ(frames[0].position.lon, expect.position.lon);
  EXPECT_DOUBLE_EQ(frames[0].depth_m, 40.25);
  EXPECT_DOUBLE_EQ(frames[0].pitch_deg, -1.5);
  EXPECT_DOUBLE_EQ(frames[0].roll_deg, 0.75);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(frames[0].footprint[i].lat, expect.footprint[i].lat);
    EXPECT_DOUBLE_EQ(frames[0].footprint[i].lon, expect.footprint[i].lon);
  }
  EXPECT_EQ(frames[0].status, "used");
  EXPECT_EQ(frames[1].status, "blurred");
  EXPECT_FALSE(frames[1].time_s.has_value());

  const auto track = store.Track();
  ASSERT_EQ(track.size(), 2u);
  EXPECT_EQ(track[0].seq, 0);
  EXPECT_FALSE(track[0].time_s.has_value());
  EXPECT_EQ(track[1].time_s, 5.0);
  EXPECT_DOUBLE_EQ(track[1].position.lat, 43.0);
  EXPECT_DOUBLE_EQ(track[1].heading_deg, 90.0);

  RawDb raw(path);  // footprint is a JSON array of [lon,lat] pairs
  EXPECT_EQ(raw.Query("SELECT footprint FROM frames WHERE id=1"), "[[5.1,43.1],[5.2,43.1],[5.2,43.0],[5.1,43.0]]");
}

TEST(MBTilesStore, ReopenContinuesExistingFile) {
  TempDir dir;
  const std::string path = (dir / "r.mbtiles").string();
  {
    MBTilesStore store(path);
    store.PutTile({1, 0, 0}, Bytes("a"));
    store.SetMetadata("name", "x");
  }
  MBTilesStore store(path);
  store.PutTile({1, 1, 0}, Bytes("b"));
  EXPECT_EQ(store.TileCount(), 2);
  EXPECT_EQ(*store.GetTile({1, 0, 0}), Bytes("a"));
  EXPECT_EQ(store.Metadata().at("name"), "x");
}

TEST(MBTilesStore, WritesBecomeVisibleToOthersOnFlush) {
  TempDir dir;
  const std::string path = (dir / "t.mbtiles").string();
  MBTilesStore store(path);
  store.Flush();
  RawDb raw(path);
  store.PutTile({2, 1, 1}, Bytes("x"));
  store.PutFrame(SampleFrame(1));
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM tiles"), "0");  // still in the open transaction
  store.Flush();
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM tiles"), "1");
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM frames"), "1");
}

TEST(MBTilesStore, LongBatchesCommitOnTheirOwn) {
  TempDir dir;
  const std::string path = (dir / "b.mbtiles").string();
  MBTilesStore store(path);
  RawDb raw(path);
  for (int i = 0; i < 499; ++i) store.PutTile({10, i, 0}, Bytes("t"));
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM tiles"), "0");
  store.PutTile({10, 499, 0}, Bytes("t"));  // the 500th write commits
  EXPECT_EQ(raw.Query("SELECT COUNT(*) FROM tiles"), "500");
}

TEST(MBTilesStore, WriterAndReaderThreads) {
  TempDir dir;
  MBTilesStore store((dir / "mt.mbtiles").string());
  constexpr int kTiles = 300;
  std::thread writer([&] {
    for (int i = 0; i < kTiles; ++i) store.PutTile({12, i, 7}, Bytes(std::to_string(i)));
    store.Flush();
  });
  for (int round = 0; round < 5; ++round)
    for (int i = 0; i < kTiles; ++i)
      if (auto t = store.GetTile({12, i, 7})) {
        EXPECT_EQ(*t, Bytes(std::to_string(i)));
      }
  writer.join();
  EXPECT_EQ(store.TileCount(), kTiles);
  EXPECT_EQ(*store.GetTile({12, kTiles - 1, 7}), Bytes(std::to_string(kTiles - 1)));
}

TEST(MBTilesStore, UncreatablePathIsInputErrorNamingIt) {
  const std::string path = "/nonexistent_dir/x.mbtiles";
  try {
    MBTilesStore store(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.field(), "--out");
    EXPECT_NE(e.detail().find("cannot create MBTiles file"), std::string::npos) << e.what();
  }
}

TEST(MBTilesStore, NonDatabaseFileIsInputError) {
  TempDir dir;
  const auto path = testing::WriteFile(dir / "bad.mbtiles", std::string(4096, 'x')).string();
  EXPECT_THROW(MBTilesStore{path}, InputError);
  EXPECT_THROW(MBTilesStore(path, MBTilesStore::Mode::kReadOnly), InputError);
}

TEST(MBTilesStore, ReadOnlyMode) {
  TempDir dir;
  const std::string path = (dir / "ro.mbtiles").string();
  EXPECT_THROW(MBTilesStore(path, MBTilesStore::Mode::kReadOnly), InputError);  // missing
  {
    sqlite3* db = nullptr;  // a SQLite file without a tiles table
    sqlite3_open((dir / "other.db").string().c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE t (a)", nullptr, nullptr, nullptr);
    sqlite3_close(db);
    try {
      MBTilesStore store((dir / "other.db").string(), MBTilesStore::Mode::kReadOnly);
      FAIL() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_NE(e.detail().find("tiles"), std::string::npos) << e.what();
    }
  }
  {
    MBTilesStore store(path);
    store.PutTile({0, 0, 0}, Bytes("z0"));
    store.SetMetadata("name", "ro");
  }
  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(*store.GetTile({0, 0, 0}), Bytes("z0"));
  EXPECT_EQ(store.Metadata().at("name"), "ro");
  EXPECT_EQ(store.TileCount(), 1);
  EXPECT_TRUE(store.Frames().empty());
  EXPECT_THROW(store.PutTile({1, 0, 0}, Bytes("no")), std::runtime_error);
}

// Web Mercator tile numbering, written out here so the test checks the
// store against the spec rather than against the geo module.
int TileX(double lon, int z) {
  return static_cast<int>(std::floor((lon + 180) / 360 * (1 << z)));
}
int TileY(double lat, int z) {
  const double r = lat * M_PI / 180;
  return static_cast<int>(std::floor((1 - std::asinh(std::tan(r)) / M_PI) / 2 * (1 << z)));
}
double MercX(int x, int z) {
  return x * kEarthCircumference / (1 << z) - kEarthCircumference / 2;
}
double MercY(int y, int z) {
  return kEarthCircumference / 2 - y * kEarthCircumference / (1 << z);
}
double Lon(int x, int z) {
  return x * 360.0 / (1 << z) - 180;
}
double Lat(int y, int z) {
  return std::atan(std::sinh(M_PI * (1 - 2.0 * y / (1 << z)))) * 180 / M_PI;
}

TEST(MBTilesStore, GdalReadsTwoZoomPyramid) {
  std::string out;
  if (RunCommand("gdalinfo --version", &out) != 0) GTEST_SKIP() << "gdalinfo not installed";
  TempDir dir;
  const std::string path = (dir / "gdal.mbtiles").string();
  // A 2x2 block of z=20 tiles near Marseille and their one z=19 parent.
  const int x0 = TileX(5.3, 20) & ~1, y0 = TileY(43.2, 20) & ~1;
  {
    MBTilesStore store(path);
    cv::Mat tile(256, 256, CV_8UC4, cv::Scalar(40, 120, 200, 255));
    const std::vector<uint8_t> png = EncodeTile(tile, {});
    for (int dx = 0; dx < 2; ++dx)
      for (int dy = 0; dy < 2; ++dy) store.PutTile({20, x0 + dx, y0 + dy}, png);
    store.PutTile({19, x0 / 2, y0 / 2}, png);
    const double w = Lon(x0, 20), e = Lon(x0 + 2, 20), n = Lat(y0, 20), s = Lat(y0 + 2, 20);
    store.SetMetadata("name", "gdal test");
    store.SetMetadata("format", "png");
    store.SetMetadata("bounds",
                      std::to_string(w) + "," + std::to_string(s) + "," + std::to_string(e) + "," + std::to_string(n));
    store.SetMetadata("center", std::to_string((w + e) / 2) + "," + std::to_string((s + n) / 2) + ",20");
    store.SetMetadata("minzoom", "19");
    store.SetMetadata("maxzoom", "20");
    store.Flush();
  }
  ASSERT_EQ(RunCommand("gdalinfo '" + path + "'", &out), 0) << out;
  EXPECT_NE(out.find("Driver: MBTiles"), std::string::npos) << out;
  EXPECT_NE(out.find("Size is 512, 512"), std::string::npos) << out;
  const std::regex corner(R"((Upper Left|Lower Right)\s*\(\s*(-?[\d.]+),\s*(-?[\d.]+)\))");
  int corners = 0;
  for (std::sregex_iterator it(out.begin(), out.end(), corner), end; it != end; ++it) {
    const bool upper = (*it)[1] == "Upper Left";
    const double x = std::stod((*it)[2]), y = std::stod((*it)[3]);
    EXPECT_NEAR(x, MercX(upper ? x0 : x0 + 2, 20), 0.5) << out;
    EXPECT_NEAR(y, MercY(upper ? y0 : y0 + 2, 20), 0.5) << out;
    ++corners;
  }
  EXPECT_EQ(corners, 2) << out;
  // One overview (z=19, 256x256) below the full-resolution z=20 level.
  const std::regex overviews(R"(Overviews: ([^\n]*))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, overviews)) << out;
  EXPECT_EQ(m[1].str(), "256x256") << out;
}

TEST(MBTilesStore, GdalReadsGrayAndGrayAlphaTiles) {
  std::string out;
  if (RunCommand("gdallocationinfo --version", &out) != 0) GTEST_SKIP() << "GDAL not installed";
  TempDir dir;
  const std::string path = (dir / "gray.mbtiles").string();
  {
    MBTilesStore store(path);
    cv::Mat half(256, 256, CV_8UC2, cv::Scalar(100, 255));  // gray+alpha PNG
    half(cv::Rect(0, 0, 128, 256)).setTo(cv::Scalar(0, 0));
    const cv::Mat opaque(256, 256, CV_8UC2, cv::Scalar(200, 255));  // plain gray PNG
    store.PutTile({1, 0, 0}, EncodeTile(half, {}));
    store.PutTile({1, 1, 0}, EncodeTile(opaque, {}));
    store.PutTile({1, 0, 1}, EncodeTile(opaque, {}));
    store.PutTile({1, 1, 1}, EncodeTile(opaque, {}));
    store.SetMetadata("name", "gray");
    store.SetMetadata("format", "png");
    store.SetMetadata("minzoom", "1");
    store.SetMetadata("maxzoom", "1");
  }
  const auto pixel = [&](int x, int y) {
    std::string values;
    RunCommand("gdallocationinfo -valonly '" + path + "' " + std::to_string(x) + " " + std::to_string(y), &values);
    std::replace(values.begin(), values.end(), '\n', ' ');
    return values;
  };
  EXPECT_EQ(pixel(10, 10), "0 0 0 0 ");
  EXPECT_EQ(pixel(200, 10), "100 100 100 255 ");
  EXPECT_EQ(pixel(300, 10), "200 200 200 255 ");
}

}  // namespace
}  // namespace seamap
