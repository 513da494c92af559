// Issue 33, the server's rows, on a real loopback server: `since` past any
// change gives nothing (not everything), /api/detections in pages with a
// `next` link, detection records with null or non-finite numbers left out
// and counted, and photos only from the mission's own photo folder (no
// symlink out, regular files only, the bytes the name says).
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <future>

#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

// Runs SQL on the mission file (what a hostile or broken writer left there).
void Sql(const std::filesystem::path& map, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(map.string().c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error ? error : "";
  sqlite3_free(error);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << message << "\n" << sql;
}

std::string InsertDetection(int id, const std::string& cls, const std::string& lat, const std::string& lon,
                            const std::string& box = "NULL", const std::string& levels = "NULL") {
  return "INSERT INTO detections (id, class, score, lat, lon, source, seq, box, levels) VALUES (" + std::to_string(id) +
         ", '" + cls + "', 0.5, " + lat + ", " + lon + ", 'recogniser', " + std::to_string(id) + ", " + box + ", " +
         levels + ");";
}

std::vector<int64_t> Ids(const json& collection) {
  std::vector<int64_t> ids;
  for (const auto& f : collection["features"]) ids.push_back(f["id"].get<int64_t>());
  return ids;
}

using HttpHostileTest = HttpServerTest;

TEST_F(HttpHostileTest, SincePastAnyChangeGivesNothingNotEverything) {
  Start();
  // 1e19 > 2^63: cast to int64 it was INT64_MIN, and every detection came back.
  for (const std::string since : {"1e19", "1e300", "9223372036854775807", "9223372036854775808", "1.8e19"}) {
    EXPECT_TRUE(GetJson("/api/detections?since=" + since)["features"].empty()) << since;
    auto bin = Get("/api/detections.bin?since=" + since);
    ASSERT_TRUE(bin);
    EXPECT_EQ(bin->status, 200);
    EXPECT_EQ(bin->get_header_value("X-SeaMap-Records"), "0") << since;
    EXPECT_TRUE(bin->body.empty()) << since;
  }
  EXPECT_EQ(Ids(GetJson("/api/detections?since=1")), (std::vector<int64_t>{2}));
  ExpectError(Get("/api/detections?since=1e400"), 400, "since", "past a double");
  ExpectError(Get("/api/detections?since=-1e19"), 400, "since", "negative");
}

TEST_F(HttpHostileTest, DetectionsComeInPagesWithANextLink) {
  std::string sql;
  for (int id = 3; id <= 9; ++id) sql += InsertDetection(id, id % 2 ? "rock" : "tyre", "43.0002", "5.0002");
  Sql(mission_.path, sql);
  Start();
  // A small list is one answer, as before: no `next`.
  const json all = GetJson("/api/detections");
  EXPECT_EQ(Ids(all).size(), 9u);
  EXPECT_FALSE(all.contains("next"));

  std::vector<int64_t> seen;
  std::string url = "/api/detections?class=rock,tyre&limit=3";
  int pages = 0;
  for (; !url.empty() && pages < 10; ++pages) {
    const json page = GetJson(url);
    EXPECT_LE(page["features"].size(), 3u);
    EXPECT_EQ(page["last_seq"], 9);
    for (int64_t id : Ids(page)) seen.push_back(id);
    url = page.contains("next") ? page["next"].get<std::string>() : "";
    if (!url.empty()) {
      EXPECT_NE(url.find("class=rock%2Ctyre"), std::string::npos) << url;  // the filter stays
    }
  }
  EXPECT_EQ(pages, 3);
  EXPECT_EQ(seen, (std::vector<int64_t>{1, 3, 4, 5, 6, 7, 8, 9}));
  EXPECT_EQ(Ids(GetJson("/api/detections?after=7")), (std::vector<int64_t>{8, 9}));
  ExpectError(Get("/api/detections?limit=0"), 400, "'limit'", "no page");
  ExpectError(Get("/api/detections?limit=5001"), 400, "'limit'", "past the page size");
  ExpectError(Get("/api/detections?after=x"), 400, "'after'", "a text id");
}

TEST_F(HttpHostileTest, APageHoldsAtMostFiveThousand) {
  std::string sql = "BEGIN;";
  for (int id = 3; id <= 5003; ++id) sql += InsertDetection(id, "rock", "43.0002", "5.0002");
  Sql(mission_.path, sql + "COMMIT;");
  Start();
  const json first = GetJson("/api/detections");
  ASSERT_EQ(first["features"].size(), 5000u);
  ASSERT_TRUE(first.contains("next"));
  EXPECT_EQ(first["next"], "/api/detections?after=5000");
  EXPECT_EQ(Ids(GetJson(first["next"].get<std::string>())), (std::vector<int64_t>{5001, 5002, 5003}));
}

TEST_F(HttpHostileTest, DetectionRecordsWithNullOrNonFiniteNumbersAreLeftOutAndCounted) {
  // What a model whose boxes came out inf/NaN stored (SQLite keeps NaN as NULL).
  Sql(mission_.path, InsertDetection(3, "nan", "NULL", "5.0") + InsertDetection(4, "inf", "9e999", "5.0") +
                         InsertDetection(5, "box", "43.0", "5.0", "'[[null,1]]'") +
                         InsertDetection(6, "json", "43.0", "5.0", "'[[5.0,'") +
                         InsertDetection(7, "levels", "43.0", "5.0", "NULL", "'[1e300]'") +
                         InsertDetection(8, "globe", "1e300", "5.0") +
                         InsertDetection(9, "fine", "43.0003", "5.0003", "'[[5.0,43.0],[5.1,43.1]]'"));
  Start();
  EXPECT_EQ(Ids(GetJson("/api/detections")), (std::vector<int64_t>{1, 2, 9}));
  EXPECT_EQ(GetJson("/api/status")["unreadable_detections"], 6);
  auto bin = Get("/api/detections.bin");
  ASSERT_TRUE(bin);
  EXPECT_EQ(bin->get_header_value("X-SeaMap-Records"), "3");
}

TEST_F(HttpHostileTest, AMissionWithEveryRecordReadableSaysNothingOfUnreadableOnes) {
  Start();
  EXPECT_FALSE(GetJson("/api/status").contains("unreadable_detections"));
}

// Frame `id`'s recorded photo path becomes `path`.
void SetImagePath(const std::filesystem::path& map, int id, const std::string& path) {
  Sql(map, "UPDATE frames SET image_path = '" + path + "' WHERE id = " + std::to_string(id) + ";");
}

TEST_F(HttpHostileTest, PhotosComeOnlyFromTheMissionsPhotoFolder) {
  const auto outside = dir_ / "elsewhere" / "private.png";  // any PNG on the server
  std::filesystem::create_directories(outside.parent_path());
  std::filesystem::copy_file(mission_.photo0, outside);
  SetImagePath(mission_.path, 1, outside.string());
  // Frame 2: a symlink in the photo folder out of it.
  std::filesystem::create_symlink(outside, dir_ / "photos" / "frame_2.png");
  Start();
  auto own = Get("/api/frames/0/image");
  ASSERT_TRUE(own);
  EXPECT_EQ(own->status, 200);
  ExpectError(Get("/api/frames/1/image"), 404, "not in the mission's photo folder", "a path out of the folder");
  ExpectError(Get("/api/frames/2/image"), 404, "not in the mission's photo folder", "a symlink out of the folder");
  ExpectError(Get("/api/frames/2/image?max=64"), 404, "not in the mission's photo folder", "its thumbnail");
}

TEST_F(HttpHostileTest, ThePhotoDirIsAFolderTooAndNamesCannotClimbOutOfIt) {
  const auto photos = dir_ / "moved";
  std::filesystem::create_directories(photos);
  std::filesystem::copy_file(mission_.photo0, photos / "gone.png");
  std::filesystem::copy_file(mission_.photo0, dir_ / "climbed.png");
  Sql(mission_.path, "UPDATE frames SET image = '../climbed.png', image_path = '/nowhere/x.png' WHERE id = 1;");
  ServerOptions o = Options();
  o.photo_dir = photos.string();
  Start(o);
  auto res = Get("/api/frames/3/image");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  ExpectError(Get("/api/frames/1/image"), 404, "nor in --images", "a name with ..");
}

TEST_F(HttpHostileTest, AFifoOrAFileThatIsNotItsImageIsRefusedAtOnce) {
  const auto fifo = dir_ / "photos" / "frame_2.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  seamap::testing::WriteFile(dir_ / "photos" / "gone.png", "TOP SECRET, not a PNG");
  Start();
  // Many at once: none may hold a thread (a FIFO opened to read waits for a writer).
  std::vector<std::future<int>> answers;
  for (int i = 0; i < 40; ++i)
    answers.push_back(std::async(std::launch::async, [this] {
      auto res = Get("/api/frames/2/image");
      return res ? res->status : -1;
    }));
  for (auto& a : answers) {
    ASSERT_EQ(a.wait_for(std::chrono::seconds(20)), std::future_status::ready);
    EXPECT_EQ(a.get(), 404);
  }
  ExpectError(Get("/api/frames/2/image"), 404, "not a regular file", "a FIFO");
  ExpectError(Get("/api/frames/3/image"), 404, "not the image/png its name says", "text named .png");
  EXPECT_EQ(GetJson("/api/status")["frames_done"], 4);
}

}  // namespace
}  // namespace seamap::server
