// Issue 33, the server's rows, on the real binary: `seamap serve FOLDER`
// with a mission whose records cannot be read (the server lives, the others
// serve), detection records with null/non-finite numbers (left out, the map
// readable by serve and detections-pack), photos outside the mission's photo
// folder, through a symlink or at a FIFO (refused at once; SIGTERM still
// stops the server), a mission file replaced while served (opened again), a
// hundred missions under a small handle limit (least recently used closed),
// and `since` past any change (nothing, not everything).
#include <sqlite3.h>
#include <sys/stat.h>

#include <csignal>
#include <filesystem>
#include <future>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::ChildProcess;

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("hostile_server", "--frames 8 --line-length 2 --seed 7 --quiet");
}

// The survey's map, built once.
const std::string& Map() {
  static const std::string path = [] {
    const std::string p = Survey().dir + "/hostile_server.mbtiles";
    std::string out;
    EXPECT_EQ(testing::Seamap(Survey().BuildArgs() + " --out " + p, &out), 0) << out;
    return p;
  }();
  return path;
}

void Sql(const fs::path& map, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(map.string().c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << message << "\n" << sql.substr(0, 300);
}

fs::path CopyMap(const fs::path& to, const std::string& sql = "") {
  fs::create_directories(to.parent_path());
  fs::copy_file(Map(), to);
  if (!sql.empty()) Sql(to, sql);
  return to;
}

std::string Detection(int id, const std::string& cls, const std::string& lat, const std::string& box = "NULL") {
  return "INSERT INTO detections (id, class, score, lat, lon, source, seq, box) VALUES (" + std::to_string(id) + ", '" +
         cls + "', 0.5, " + lat + ", 131.9, 'recogniser', " + std::to_string(id) + ", " + box + ");";
}

// `seamap serve FOLDER` on a loopback port, with at most `max_files` open files.
struct Server {
  Server(const fs::path& folder, const fs::path& log, int max_files = 1024)
      : process({"/bin/sh", "-c",
                 "ulimit -n " + std::to_string(max_files) + " && exec " + testing::SeamapBinary() + " serve '" +
                     folder.string() + "' --host 127.0.0.1 --port 0"},
                log.string()) {
    auto line = process.WaitForLine("serving", std::chrono::seconds(30));
    EXPECT_TRUE(line);
    port = line ? testing::PortFromServingLine(*line) : 0;
  }
  httplib::Result Get(const std::string& path) {
    httplib::Client c("127.0.0.1", port);
    c.set_read_timeout(30);
    return c.Get(path.c_str());
  }
  json GetJson(const std::string& path, int status = 200) {
    auto res = Get(path);
    EXPECT_TRUE(res) << path;
    if (!res) return nullptr;
    EXPECT_EQ(res->status, status) << path << ": " << res->body.substr(0, 300);
    return json::parse(res->body, nullptr, false);
  }
  std::string Error(const std::string& path, int status) {
    const json j = GetJson(path, status);
    return j.is_object() && j.contains("error") ? j["error"].get<std::string>() : "";
  }
  ChildProcess process;
  int port = 0;
};

std::vector<std::string> Classes(const json& collection) {
  std::vector<std::string> out;
  if (collection.is_object())
    for (const auto& f : collection["features"]) out.push_back(f["properties"]["class"].get<std::string>());
  return out;
}

TEST(HostileServer, AMissionWhoseRecordsCannotBeReadAnswersAloneAndTheServerLives) {
  testing::TempDir dir;
  const fs::path folder = dir / "maps";
  CopyMap(folder / "good.mbtiles", Detection(1, "crate", "43.1"));
  // Row 1: a frame's footprint [[null,1]] cannot be read at all.
  CopyMap(folder / "unreadable.mbtiles", "UPDATE frames SET footprint = '[[null,1]]' WHERE id = 2;");
  // Row 3's reader side: what a model whose boxes came out inf/NaN stored.
  CopyMap(folder / "nan.mbtiles", Detection(1, "crate", "43.1") + Detection(2, "nan", "NULL", "'[[null,null]]'") +
                                      Detection(3, "box", "43.1", "'[[null,1]]'") + Detection(4, "inf", "9e999"));
  Server s(folder, dir / "serve.err");
  for (int i = 0; i < 3; ++i) {
    const std::string error = s.Error("/missions/unreadable/api/status", 404);
    EXPECT_NE(error.find("mission 'unreadable' is unavailable"), std::string::npos) << error;
    EXPECT_NE(error.find("type must be number"), std::string::npos) << error;
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // the follower runs every 2 s
  }
  EXPECT_NE(s.Error("/missions/unreadable/api/events", 404).find("unreadable"), std::string::npos);
  EXPECT_NE(s.Error("/missions/unreadable/tiles.json", 404).find("unreadable"), std::string::npos);
  EXPECT_FALSE(s.process.Wait(std::chrono::seconds(0))) << "the server died";
  EXPECT_EQ(s.GetJson("/missions/good/api/status")["frames_done"], 8);
  EXPECT_EQ(Classes(s.GetJson("/missions/good/api/detections")), std::vector<std::string>{"crate"});

  EXPECT_EQ(Classes(s.GetJson("/missions/nan/api/detections")), std::vector<std::string>{"crate"});
  EXPECT_EQ(s.GetJson("/missions/nan/api/status")["unreadable_detections"], 3);
  // Row 8 on the binary: since past any change.
  EXPECT_TRUE(s.GetJson("/missions/nan/api/detections?since=1e19")["features"].empty());
  auto bin = s.Get("/missions/nan/api/detections.bin?since=1e300");
  ASSERT_TRUE(bin);
  EXPECT_EQ(bin->get_header_value("X-SeaMap-Records"), "0");
  EXPECT_FALSE(s.process.Wait(std::chrono::seconds(0))) << "the server died";

  // The other readers of the same map: the readable detections, exit 0.
  std::string out;
  EXPECT_EQ(testing::Seamap(
                "detections-pack " + (folder / "nan.mbtiles").string() + " --out " + (dir / "nan.bin").string(), &out),
            0)
      << out;
  EXPECT_EQ(fs::file_size(dir / "nan.bin"), 24u) << out;
}

TEST(HostileServer, PhotosComeOnlyFromTheMissionsOwnFolderAndAFifoHoldsNoThread) {
  testing::TempDir dir;
  const fs::path photos = dir / "photo";
  fs::copy(Survey().photo, photos);
  const fs::path secret = dir / "private" / "secret.png";  // any image on the server
  fs::create_directories(secret.parent_path());
  fs::copy_file(photos / "frame_000000.png", secret);
  const fs::path folder = dir / "maps";
  CopyMap(folder / "dive.mbtiles", "UPDATE frames SET image_path = '" + photos.string() + "/' || image;" +
                                       "UPDATE frames SET image_path = '" + secret.string() + "' WHERE id = 0;");
  fs::remove(photos / "frame_000001.png");
  ASSERT_EQ(::mkfifo((photos / "frame_000001.png").c_str(), 0600), 0);
  fs::remove(photos / "frame_000002.png");
  fs::create_symlink(secret, photos / "frame_000002.png");

  Server s(folder, dir / "serve.err");
  EXPECT_NE(s.Error("/missions/dive/api/frames/0/image", 404).find("not in the mission's photo folder"),
            std::string::npos);
  EXPECT_NE(s.Error("/missions/dive/api/frames/2/image", 404).find("not in the mission's photo folder"),
            std::string::npos);
  EXPECT_NE(s.Error("/missions/dive/api/frames/1/image", 404).find("not a regular file"), std::string::npos);
  // 160 requests at the FIFO (130 used to stall the server): each answered at once.
  std::vector<std::future<int>> answers;
  for (int t = 0; t < 8; ++t)
    answers.push_back(std::async(std::launch::async, [&s] {
      int refused = 0;
      for (int i = 0; i < 20; ++i) {
        auto res = s.Get(i % 2 ? "/missions/dive/api/frames/1/image" : "/missions/dive/api/frames/1/image?max=64");
        refused += res && res->status == 404;
      }
      return refused;
    }));
  for (auto& a : answers) {
    ASSERT_EQ(a.wait_for(std::chrono::seconds(60)), std::future_status::ready);
    EXPECT_EQ(a.get(), 20);
  }
  EXPECT_EQ(s.GetJson("/missions/dive/api/status")["frames_done"], 8);
  auto own = s.Get("/missions/dive/api/frames/3/image");
  ASSERT_TRUE(own);
  EXPECT_EQ(own->status, 200);
  EXPECT_EQ(own->body.size(), fs::file_size(photos / "frame_000003.png"));
  s.process.Signal(SIGTERM);
  EXPECT_EQ(s.process.Wait(std::chrono::seconds(15)), 0) << "SIGTERM must stop the server";
}

TEST(HostileServer, AMissionFileReplacedWhileServedIsOpenedAgain) {
  testing::TempDir dir;
  const fs::path folder = dir / "maps";
  const fs::path dive = CopyMap(folder / "dive.mbtiles", Detection(1, "crate", "43.1"));
  // The same map, another object, and its first tile another's bytes.
  const fs::path next = CopyMap(dir / "next.mbtiles", Detection(1, "pipe", "43.1") +
                                                          "UPDATE tiles SET tile_data = (SELECT tile_data FROM tiles "
                                                          "ORDER BY rowid DESC LIMIT 1) WHERE rowid = (SELECT "
                                                          "min(rowid) FROM tiles);");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dive.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT zoom_level, tile_column, tile_row FROM tiles ORDER BY rowid LIMIT 1", -1, &q,
                               nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(q), SQLITE_ROW);
  const int z = sqlite3_column_int(q, 0), x = sqlite3_column_int(q, 1);
  const int y = (1 << z) - 1 - sqlite3_column_int(q, 2);  // TMS rows
  sqlite3_finalize(q);
  sqlite3_close(db);
  const std::string tile =
      "/missions/dive/tiles/" + std::to_string(z) + "/" + std::to_string(x) + "/" + std::to_string(y) + ".png";

  Server s(folder, dir / "serve.err");
  EXPECT_EQ(Classes(s.GetJson("/missions/dive/api/detections")), std::vector<std::string>{"crate"});
  auto before = s.Get(tile);
  ASSERT_TRUE(before);
  ASSERT_EQ(before->status, 200);
  fs::rename(next, dive);  // mv: another file under the same name
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  EXPECT_EQ(Classes(s.GetJson("/missions/dive/api/detections")), std::vector<std::string>{"pipe"});
  auto after = s.Get(tile);
  ASSERT_TRUE(after);
  EXPECT_EQ(after->status, 200);
  EXPECT_NE(after->body, before->body) << "the old file's tile";
}

TEST(HostileServer, AHundredMissionsUnderFiveHundredFileHandles) {
  testing::TempDir dir;
  const fs::path folder = dir / "maps";
  for (int i = 0; i < 100; ++i) CopyMap(folder / ("d" + std::to_string(i) + ".mbtiles"));
  Server s(folder, dir / "serve.err", 512);  // ~11 handles a mission: 46 missions used to fill it
  const json tilejson = s.GetJson("/missions/d0/tiles.json");
  ASSERT_TRUE(tilejson.is_object());
  int ok = 0;
  for (int round = 0; round < 2; ++round)
    for (int i = 0; i < 100; ++i) {
      const std::string id = "/missions/d" + std::to_string(i);
      auto status = s.Get(id + "/api/status");
      auto track = s.Get(id + "/api/track");
      ok += status && status->status == 200 && track && track->status == 200;
    }
  EXPECT_EQ(ok, 200);
  EXPECT_FALSE(s.process.Wait(std::chrono::seconds(0))) << "the server died";
}

}  // namespace
}  // namespace seamap
