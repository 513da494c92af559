// `seamap replay`, `serve` and `export` as an operator meets them: a real
// process, a real port on loopback, a real MBTiles file.
#include <httplib.h>

#include <signal.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/tiles/folder_store.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_version.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap::testing {
namespace {
namespace fs = std::filesystem;
using std::chrono::seconds;

const std::string kWeb = std::string(SEAMAP_SOURCE_DIR) + "/web";

struct SseEvent {
  std::string type;
  nlohmann::json data;
};

// Parses "event: T\ndata: D\n\n" blocks out of a growing buffer.
std::vector<SseEvent> ParseEvents(std::string* buffer) {
  std::vector<SseEvent> out;
  size_t end;
  while ((end = buffer->find("\n\n")) != std::string::npos) {
    std::string block = buffer->substr(0, end);
    buffer->erase(0, end + 2);
    SseEvent e;
    std::string data;
    size_t start = 0;
    while (start <= block.size()) {
      size_t nl = block.find('\n', start);
      std::string line = block.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
      if (line.rfind("event: ", 0) == 0) e.type = line.substr(7);
      if (line.rfind("data: ", 0) == 0) data = line.substr(6);
      if (nl == std::string::npos) break;
      start = nl + 1;
    }
    if (!e.type.empty()) {
      e.data = nlohmann::json::parse(data);
      out.push_back(e);
    }
  }
  return out;
}

std::vector<std::string> ReplayArgs(const SimulatedSurvey& s, const std::string& out, const std::string& speed) {
  return {SeamapBinary(), "replay", s.dir, "--out", out,  "--speed", speed,    "--host",
          "127.0.0.1",    "--port", "0",   "--web", kWeb, "--token", "secret", "--quiet"};
}

TEST(LiveServer, ReplayStreamsEventsForTilesPosesTrackAndProgressAndKeepsMarks) {
  const SimulatedSurvey& survey = SharedSurvey("replay", "--frames 60");
  TempDir tmp;
  const std::string mission = (tmp / "live.mbtiles").string();
  ChildProcess replay(ReplayArgs(survey, mission, "4"), (tmp / "replay.err").string());
  auto line = replay.WaitForLine("serving http://", seconds(60));
  ASSERT_TRUE(line) << "no serving line; stdout: " << replay.output();
  const int port = PortFromServingLine(*line);
  ASSERT_GT(port, 0);

  // Listen to the live events while the replay runs.
  std::map<std::string, int> counts;
  std::vector<SseEvent> tiles;
  std::atomic<bool> done{false}, connected{false};
  std::thread listener([&] {
    httplib::Client events("127.0.0.1", port);
    events.set_read_timeout(60, 0);
    std::string buffer;
    events.Get("/api/events", [&](const char* data, size_t n) {
      connected = true;
      buffer.append(data, n);
      for (auto& e : ParseEvents(&buffer)) {
        ++counts[e.type];
        if (e.type == "tile") tiles.push_back(e);
        if (e.type == "progress" && e.data.value("state", "") == "complete") done = true;
      }
      return !done;
    });
  });

  // An operator marks an object meanwhile (once the stream is open, so it hears
  // of it): refused without the token, kept with it.
  for (int i = 0; i < 600 && !connected; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_TRUE(connected) << "the event stream never opened";
  httplib::Client api("127.0.0.1", port);
  const std::string mark =
      R"({"type":"Feature","geometry":{"type":"Point","coordinates":[131.90001,43.10003]},"properties":{"class":"tyre","note":"half buried"}})";
  auto refused = api.Post("/api/detections", mark, "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 401);
  httplib::Headers auth = {{"Authorization", "Bearer secret"}};
  auto created = api.Post("/api/detections", auth, mark, "application/json");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;

  listener.join();
  ASSERT_TRUE(done) << "the replay never announced completion";
  EXPECT_GT(counts["tile"], 0);
  EXPECT_GE(counts["pose"], 10);
  EXPECT_GE(counts["track"], 10);
  EXPECT_GE(counts["progress"], 2);
  EXPECT_EQ(counts["detection"], 1);

  // A tile event's version is the ETag of that tile as served (the last event of each tile).
  std::map<std::string, std::string> latest;
  for (const auto& e : tiles)
    latest[std::to_string(e.data["z"].get<int>()) + "/" + std::to_string(e.data["x"].get<int>()) + "/" +
           std::to_string(e.data["y"].get<int>())] = e.data["version"];
  int checked = 0;
  for (const auto& [path, version] : latest) {
    auto res = api.Get("/tiles/" + path + ".png");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->get_header_value("ETag"), "\"" + version + "\"") << path;
    if (++checked == 20) break;
  }
  auto status = api.Get("/api/status");
  ASSERT_TRUE(status);
  auto s = nlohmann::json::parse(status->body);
  EXPECT_EQ(s["state"], "complete");
  EXPECT_EQ(s["frames_done"], 60);
  EXPECT_EQ(s["replay"], true);

  // It keeps serving the finished mission until told to stop.
  EXPECT_TRUE(replay.WaitForLine("still serving", seconds(30))) << replay.output();
  replay.Signal(SIGTERM);
  auto code = replay.Wait(seconds(60));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0) << replay.output();
  // The mark lives in the mission file, next to frames and track.
  MBTilesStore store(mission, MBTilesStore::Mode::kReadOnly);
  auto detections = store.Detections();
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].class_name, "tyre");
  EXPECT_EQ(detections[0].note, "half buried");
  EXPECT_EQ(store.Frames().size(), 60u);
  EXPECT_EQ(store.Metadata()["seamap_state"], "complete");
}

TEST(LiveServer, ServesAnExportedFolderTileForTileLikeTheMbtiles) {
  const SimulatedSurvey& survey = SharedSurvey("serve", "--frames 40");
  TempDir tmp;
  const std::string mission = (tmp / "m.mbtiles").string(), folder = (tmp / "tiles").string();
  std::string out;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --quiet --out " + mission, &out), 0) << out;
  ASSERT_EQ(Seamap("export " + mission + " " + folder + " --quiet", &out), 0) << out;

  MBTilesStore store(mission, MBTilesStore::Mode::kReadOnly);
  const auto ids = store.TileIds();
  ASSERT_FALSE(ids.empty());
  ChildProcess serve({SeamapBinary(), "serve", folder, "--host", "127.0.0.1", "--port", "0", "--web", kWeb});
  auto line = serve.WaitForLine("serving http://", seconds(30));
  ASSERT_TRUE(line) << serve.output();
  httplib::Client api("127.0.0.1", PortFromServingLine(*line));
  for (const TileId& id : ids) {
    auto res =
        api.Get("/tiles/" + std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200);
    auto bytes = store.GetTile(id);
    ASSERT_TRUE(bytes);
    EXPECT_EQ(res->body, std::string(bytes->begin(), bytes->end()));
    EXPECT_EQ(res->get_header_value("ETag"), "\"" + TileVersionHex(TileVersion(*bytes)) + "\"");
  }
  auto tilejson = api.Get("/tiles.json");
  ASSERT_TRUE(tilejson);
  auto j = nlohmann::json::parse(tilejson->body);
  EXPECT_EQ(j["tilejson"], "3.0.0");
  EXPECT_EQ(j["maxzoom"], nlohmann::json::parse(store.Metadata()["maxzoom"]));
  // The console is served from web/.
  auto index = api.Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_NE(index->body.find("<html"), std::string::npos);
  // Photos of the mission: the frames covering the centre of the first used footprint.
  auto frames = store.Frames();
  ASSERT_FALSE(frames.empty());
  double lat = 0, lon = 0;
  for (const auto& c : frames[5].footprint) {
    lat += c.lat / 4;
    lon += c.lon / 4;
  }
  auto covering = api.Get("/api/frames?lat=" + std::to_string(lat) + "&lon=" + std::to_string(lon));
  ASSERT_TRUE(covering);
  auto list = nlohmann::json::parse(covering->body)["frames"];
  ASSERT_FALSE(list.empty());
  std::set<int> ids_found;
  for (const auto& f : list) ids_found.insert(f["id"].get<int>());
  EXPECT_TRUE(ids_found.count(5));
  auto photo = api.Get("/api/frames/5/image");
  ASSERT_TRUE(photo);
  EXPECT_EQ(photo->status, 200);
  std::ifstream original(frames[5].image_path, std::ios::binary);
  EXPECT_EQ(photo->body, std::string(std::istreambuf_iterator<char>(original), {}));
}

TEST(LiveServer, ServeFollowsAMissionAnotherProcessIsBuilding) {
  const SimulatedSurvey& survey = SharedSurvey("follow", "--frames 30");
  TempDir tmp;
  const std::string mission = (tmp / "m.mbtiles").string();
  // 8 s of replay (30 frames at 5 frames/s, 0.75x): long enough for a `serve`
  // started on a loaded machine to see the mission while it is being built.
  ChildProcess replay({SeamapBinary(), "replay", survey.dir, "--out", mission, "--speed", "0.75", "--host", "127.0.0.1",
                       "--port", "0", "--web", kWeb, "--quiet", "--exit-when-done"});
  ASSERT_TRUE(replay.WaitForLine("serving http://", seconds(60))) << replay.output();
  ChildProcess serve({SeamapBinary(), "serve", mission, "--host", "127.0.0.1", "--port", "0", "--web", kWeb});
  auto line = serve.WaitForLine("serving http://", seconds(30));
  ASSERT_TRUE(line) << serve.output();
  httplib::Client api("127.0.0.1", PortFromServingLine(*line));
  std::set<std::string> states;
  nlohmann::json status;
  for (int i = 0; i < 300; ++i) {
    auto res = api.Get("/api/status");
    ASSERT_TRUE(res);
    status = nlohmann::json::parse(res->body);
    states.insert(status["state"].get<std::string>());
    if (status["state"] == "complete" && status["track_points"] == 30) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(states.count("building")) << "never saw the mission being built";
  EXPECT_EQ(status["state"], "complete");
  EXPECT_EQ(status["track_points"], 30);
  auto code = replay.Wait(seconds(60));
  ASSERT_TRUE(code);
  EXPECT_EQ(*code, 0);
}

TEST(LiveServer, ReplayTakesTheSurveysOriginWithEveryDigit) {
  const SimulatedSurvey& survey = SharedSurvey("origin", "--frames 10 --origin 43.12345678,131.98765432");
  TempDir tmp;
  const std::string mission = (tmp / "m.mbtiles").string();
  ChildProcess replay({SeamapBinary(), "replay", survey.dir, "--out", mission, "--speed", "max", "--host", "127.0.0.1",
                       "--port", "0", "--web", kWeb, "--quiet", "--exit-when-done"});
  auto code = replay.Wait(seconds(120));
  ASSERT_TRUE(code);
  ASSERT_EQ(*code, 0) << replay.output();
  MBTilesStore store(mission, MBTilesStore::Mode::kReadOnly);
  double lat = 0, lon = 0;
  ASSERT_EQ(std::sscanf(store.Metadata()["seamap_origin"].c_str(), "%lf,%lf", &lat, &lon), 2);
  EXPECT_NEAR(lat, 43.12345678, 1e-7);  // six decimals would be 2-3e-7 off (up to 5 cm)
  EXPECT_NEAR(lon, 131.98765432, 1e-7);
}

TEST(LiveServer, WatchBuildsFramesAsTheyAppearInAFolder) {
  const SimulatedSurvey& survey = SharedSurvey("watch", "--frames 30");
  TempDir tmp;
  const fs::path dive = tmp / "dive";
  fs::create_directories(dive / "photo");
  fs::copy_file(survey.camera, dive / "camera.json");
  // Navigation and photos arrive while the replay watches.
  std::ifstream nav_in(survey.nav);
  std::vector<std::string> lines;
  for (std::string l; std::getline(nav_in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 31u);
  ChildProcess watch({SeamapBinary(), "replay", "--watch", dive.string(), "--origin", survey.origin, "--out",
                      (tmp / "w.mbtiles").string(), "--host", "127.0.0.1", "--port", "0", "--web", kWeb,
                      "--idle-timeout", "3", "--exit-when-done", "--quiet"},
                     (tmp / "watch.err").string());
  {
    std::ofstream nav(dive / "nav.csv");
    nav << lines[0] << "\n" << std::flush;
    for (size_t i = 1; i < lines.size(); ++i) {
      const std::string image = lines[i].substr(0, lines[i].find(','));
      fs::copy_file(fs::path(survey.photo) / image, dive / "photo" / image);
      nav << lines[i] << "\n" << std::flush;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  auto code = watch.Wait(seconds(120));
  ASSERT_TRUE(code) << "the watch never finished";
  EXPECT_EQ(*code, 0) << watch.output();
  EXPECT_NE(watch.output().find("frames used 30, rejected 0"), std::string::npos) << watch.output();
  MBTilesStore store((tmp / "w.mbtiles").string(), MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(store.Frames().size(), 30u);
  EXPECT_GT(store.TileCount(), 0);
}

TEST(LiveServer, BadCommandLinesGetErrorsNamingTheParameter) {
  std::string out;
  EXPECT_EQ(Seamap("serve /nonexistent/m.mbtiles --port 0", &out), 2);
  EXPECT_NE(out.find("/nonexistent/m.mbtiles"), std::string::npos) << out;
  EXPECT_EQ(Seamap("serve", &out), 2);
  EXPECT_NE(out.find("MAP"), std::string::npos) << out;
  EXPECT_EQ(Seamap("replay /nonexistent/survey --out x.mbtiles", &out), 2);
  EXPECT_NE(out.find("SURVEY"), std::string::npos) << out;
  const SimulatedSurvey& survey = SharedSurvey("bad", "--frames 5");
  TempDir tmp;
  EXPECT_EQ(Seamap("replay " + survey.dir + " --out " + (tmp / "m.mbtiles").string() + " --speed fast", &out), 2);
  EXPECT_NE(out.find("--speed"), std::string::npos) << out;
  EXPECT_EQ(Seamap("replay " + survey.dir + " --out " + (tmp / "m.mbtiles").string() + " --port 70000", &out), 2);
  EXPECT_NE(out.find("--port"), std::string::npos) << out;
  EXPECT_EQ(Seamap("export " + (tmp / "none.mbtiles").string() + " " + (tmp / "f").string(), &out), 2);
  EXPECT_NE(out.find("none.mbtiles"), std::string::npos) << out;
  // Exporting a map onto itself is refused, and the map survives.
  const std::string map = (tmp / "same.mbtiles").string();
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --quiet --out " + map, &out), 0) << out;
  EXPECT_EQ(Seamap("export " + map + " " + map + " --overwrite", &out), 2);
  EXPECT_NE(out.find("is the map being exported"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(map));
  EXPECT_GT(MBTilesStore(map, MBTilesStore::Mode::kReadOnly).TileCount(), 0);
}

TEST(LiveServer, AppendingAMissionContinuesItsFramesAndTrack) {
  const SimulatedSurvey& survey = SharedSurvey("append", "--frames 20");
  TempDir tmp;
  const std::string map = (tmp / "m.mbtiles").string();
  // The first 10 frames, then the whole survey appended: its first 10 are in the map already.
  const std::string first_half = (tmp / "first_half.csv").string();
  {
    std::ifstream in(survey.nav);
    std::ofstream half(first_half);
    std::string line;
    for (int i = 0; i <= 10 && std::getline(in, line); ++i) half << line << "\n";
  }
  const std::string args = survey.BuildArgs();
  const std::string first_args =
      args.substr(0, args.find(" --nav ")) + " --nav " + first_half + args.substr(args.find(" --camera "));
  std::string out;
  ASSERT_EQ(Seamap(first_args + " --quiet --out " + map, &out), 0) << out;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --quiet --append --out " + map, &out), 0) << out;
  MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
  auto frames = store.Frames();
  auto track = store.Track();
  ASSERT_EQ(frames.size(), 20u);
  ASSERT_EQ(track.size(), 20u);
  EXPECT_EQ(frames.back().id, 19);
  EXPECT_EQ(track.back().seq, 19);
  std::set<std::string> images;
  for (const auto& f : frames) images.insert(f.image);
  EXPECT_EQ(images.size(), 20u) << "each photo once";
}

}  // namespace
}  // namespace seamap::testing
