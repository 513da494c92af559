// `seamap serve FOLDER` on a real loopback port: the mission index, each
// mission's TileJSON and tiles under its own prefix, 20 missions at once,
// broken files listed with the reason, maps added while serving, and each
// mission's own API (read-only) and console under /missions/{id}/.
#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap {
namespace {

using testing::ChildProcess;
using testing::Seamap;
namespace fs = std::filesystem;

const std::string& CatalogueMap() {
  static const std::string path = [] {
    const auto& survey = testing::SharedSurvey("catalogue", "--frames 12 --line-length 2 --seed 3");
    const std::string p = survey.dir + "/map.mbtiles";
    std::string out;
    EXPECT_EQ(Seamap(survey.BuildArgs() + " --out " + p, &out), 0) << out;
    return p;
  }();
  return path;
}

nlohmann::json GetJson(httplib::Client& c, const std::string& path, int want_status = 200) {
  auto res = c.Get(path);
  EXPECT_TRUE(res) << path;
  if (!res) return nullptr;
  EXPECT_EQ(res->status, want_status) << path << ": " << res->body;
  return nlohmann::json::parse(res->body, nullptr, false);
}

// The tile URL of the TileJSON, for one tile, as a path on the server.
std::string TilePath(const nlohmann::json& tilejson, const TileId& t) {
  std::string url = tilejson["tiles"][0].get<std::string>();
  url = url.substr(url.find('/', std::string("http://").size()));  // drop scheme and host
  for (auto [key, value] : {std::pair<std::string, int>{"{z}", t.z}, {"{x}", t.x}, {"{y}", t.y}})
    url.replace(url.find(key), key.size(), std::to_string(value));
  return url;
}

TEST(Catalogue, ServesTwentyMissionsEachUnderItsOwnPrefix) {
  testing::TempDir dir;
  const fs::path folder = dir / "missions";
  fs::create_directories(folder);
  for (int i = 1; i <= 20; ++i) fs::copy_file(CatalogueMap(), folder / ("dive" + std::to_string(i) + ".mbtiles"));
  testing::WriteFile(folder / "broken.mbtiles", "half a file");
  auto store = OpenExistingMap(CatalogueMap(), false);
  const auto ids = store->TileIds();
  ASSERT_FALSE(ids.empty());

  ChildProcess serve({testing::SeamapBinary(), "serve", folder.string(), "--host", "127.0.0.1", "--port", "0"},
                     (dir / "serve.err").string());
  auto line = serve.WaitForLine("serving", std::chrono::seconds(20));
  ASSERT_TRUE(line);
  EXPECT_NE(line->find("21 missions, 20 available"), std::string::npos) << *line;
  httplib::Client api("127.0.0.1", testing::PortFromServingLine(*line));

  const auto missions = GetJson(api, "/api/missions");
  ASSERT_TRUE(missions.is_array());
  ASSERT_EQ(missions.size(), 21u);
  int served = 0;
  for (const auto& m : missions) {
    if (m["id"] == "broken") {
      EXPECT_EQ(m["state"], "unavailable");
      EXPECT_NE(m["reason"].get<std::string>().find("broken.mbtiles"), std::string::npos) << m.dump();
      const auto error = GetJson(api, "/missions/broken/tiles.json", 404);
      EXPECT_NE(error["error"].get<std::string>().find("unavailable"), std::string::npos);
      continue;
    }
    EXPECT_EQ(m["state"], "complete");
    EXPECT_EQ(m["frames"], 12);
    EXPECT_EQ(m["bounds"].size(), 4u);
    EXPECT_EQ(m["layers"][0], "raw");
    const auto tilejson = GetJson(api, m["tilejson"].get<std::string>());
    ASSERT_TRUE(tilejson.is_object());
    // Each mission's tiles are its own: every tile of a few, one of each of the others.
    const size_t n = served < 2 ? ids.size() : 1;
    for (size_t i = 0; i < n; ++i) {
      const TileId t = ids[(i + served) % ids.size()];
      auto res = api.Get(TilePath(tilejson, t));
      ASSERT_TRUE(res);
      ASSERT_EQ(res->status, 200) << TilePath(tilejson, t);
      const auto bytes = store->GetTile(t);
      EXPECT_EQ(res->body, std::string(bytes->begin(), bytes->end()));
    }
    ++served;
  }
  EXPECT_EQ(served, 20);
  const auto none = GetJson(api, "/missions/nope/tiles/1/0/0.png", 404);
  EXPECT_NE(none["error"].get<std::string>().find("no mission 'nope'"), std::string::npos) << none.dump();
  EXPECT_EQ(GetJson(api, "/missions/dive1/tiles/1/0/0.png", 204).is_discarded(), true);  // no tile there

  // A dive copied in while serving appears (the listing is at most a second old).
  fs::copy_file(CatalogueMap(), folder / "new dive.mbtiles");
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  bool found = false;
  for (const auto& m : GetJson(api, "/api/missions"))
    if (m["id"] == "new-dive") found = GetJson(api, m["tilejson"].get<std::string>()).is_object();
  EXPECT_TRUE(found);
}

TEST(Catalogue, EachMissionHasItsOwnReadOnlyApiAndConsole) {
  testing::TempDir dir;
  const fs::path folder = dir / "missions";
  fs::create_directories(folder);
  fs::copy_file(CatalogueMap(), folder / "dive_a.mbtiles");
  fs::copy_file(CatalogueMap(), folder / "dive_b.mbtiles");
  ChildProcess serve({testing::SeamapBinary(), "serve", folder.string(), "--host", "127.0.0.1", "--port", "0"},
                     (dir / "serve.err").string());
  auto line = serve.WaitForLine("serving", std::chrono::seconds(20));
  ASSERT_TRUE(line);
  httplib::Client api("127.0.0.1", testing::PortFromServingLine(*line));

  auto records = OpenExistingMap(CatalogueMap(), false);
  const auto status = GetJson(api, "/missions/dive_b/api/status");
  EXPECT_EQ(status["state"], "complete");
  EXPECT_EQ(status["frames_done"], 12);
  EXPECT_EQ(status["track_points"], records->Records().Track().size());
  EXPECT_EQ(status["writable"], false) << status.dump();  // a catalogue serves its missions read-only
  const auto track = GetJson(api, "/missions/dive_b/api/track");
  EXPECT_EQ(track["geometry"]["coordinates"].size(), records->Records().Track().size());
  const auto frame = GetJson(api, "/missions/dive_b/api/frames/3");
  EXPECT_EQ(frame["id"], 3);
  EXPECT_TRUE(GetJson(api, "/missions/dive_b/api/detections")["features"].is_array());
  auto write = api.Post("/missions/dive_b/api/detections",
                        R"({"type":"Feature","geometry":{"type":"Point","coordinates":[131.9,43.1]},)"
                        R"("properties":{"class":"tyre"}})",
                        "application/json");
  ASSERT_TRUE(write);
  EXPECT_GE(write->status, 400) << write->body;
  EXPECT_TRUE(
      OpenExistingMap((folder / "dive_b.mbtiles").string(), false)->Records().Detections().empty());  // nothing written
  // Unknown missions and endpoints are JSON 404s naming what is missing.
  EXPECT_NE(GetJson(api, "/missions/nope/api/status", 404)["error"].get<std::string>().find("no mission 'nope'"),
            std::string::npos);
  EXPECT_NE(GetJson(api, "/missions/dive_a/api/nothing", 404)["error"].get<std::string>().find("no such API"),
            std::string::npos);
  // The console of a mission, and the bare prefix sent there.
  auto console = api.Get("/missions/dive_a/");
  ASSERT_TRUE(console);
  EXPECT_EQ(console->status, 200);
  EXPECT_NE(console->body.find("/js/main.js"), std::string::npos);
  auto bare = api.Get("/missions/dive_a");
  ASSERT_TRUE(bare);
  EXPECT_EQ(bare->status, 302);
  EXPECT_EQ(bare->get_header_value("Location"), "/missions/dive_a/");
  EXPECT_EQ(GetJson(api, "/missions/nope/", 404).is_object(), true);

  // Another process stores a detection in an open mission (stereo-locate --map,
  // seamap detect): the catalogue serves it within a few seconds.
  {
    auto writer = OpenExistingMap((folder / "dive_b.mbtiles").string(), true);
    Detection d;
    d.id = 1;
    d.seq = 1;
    d.class_name = "wellhead";
    d.source = "stereo";
    d.position = {43.1, 131.9};
    d.heading_deg = 75;
    writer->Records().PutDetection(d);
    writer->Flush();
  }
  nlohmann::json served;
  for (int tries = 0; tries < 60 && served.empty(); ++tries) {
    served = GetJson(api, "/missions/dive_b/api/detections")["features"];
    if (served.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(served.size(), 1u) << "the catalogue never showed the detection another process stored";
  EXPECT_EQ(served[0]["properties"]["class"], "wellhead");
  EXPECT_EQ(served[0]["properties"]["heading_deg"], 75);
  EXPECT_TRUE(GetJson(api, "/missions/dive_a/api/detections")["features"].empty());
}

}  // namespace
}  // namespace seamap
