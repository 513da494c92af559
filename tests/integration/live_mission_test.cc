// The whole mission live (issue 30): what a live correction, and the end of
// the dive's, carry beyond the raw map. On a small drifting survey with
// objects, `replay --refine-nav --detect` with the raw and enhanced layers:
// the recogniser searches the tiles painted again, so the mission's objects
// lie where the refined map shows them (as build --refine-nav --detect puts
// them), not where the drifting navigation painted them; and the enhanced
// layer's tiles are painted again with the raw layer's during the dive.
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap {
namespace {

using std::chrono::seconds;
using testing::Seamap;

// 72 frames (14 s) over three 3 m lines 0.9 m apart, the navigation drifting
// 1 m/min (up to 0.2 m off by the end), 4 objects on the seabed.
const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("live_mission_objects",
                               "--frames 72 --line-length 3 --line-spacing 0.9 --nav-drift 1 --nav-noise 0.005 "
                               "--heading-noise 0.5 --objects 4 --image-format jpg --seed 7 --quiet");
}

const char kNoise[] = " --nav-noise 0.005 --nav-drift 1 --heading-noise 0.5";

struct TruthObject {
  std::string cls;
  LatLon at;
};

std::vector<TruthObject> Truth() {
  std::vector<TruthObject> truth;
  std::ifstream in(Survey().dir + "/truth/objects.csv");
  std::string line;
  std::getline(in, line);  // class,lat,lon,x_m,y_m,size_m
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    TruthObject t;
    std::string lat, lon;
    std::getline(ss, t.cls, ',');
    std::getline(ss, lat, ',');
    std::getline(ss, lon, ',');
    t.at = {std::stod(lat), std::stod(lon)};
    truth.push_back(t);
  }
  return truth;
}

std::vector<Detection> Recognised(const std::string& map) {
  MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
  std::vector<Detection> found;
  for (const Detection& d : store.Records().Detections())
    if (d.source == "recogniser") found.push_back(d);
  return found;
}

double MetresApart(const LatLon& a, const LatLon& b) {
  const LocalFrame frame(a);
  const LocalXY d = frame.FromLatLon(b);
  return std::hypot(d.east, d.north);
}

// Each true object's distance to the nearest detection of its class (none within 0.5 m: left out).
std::vector<double> ErrorsM(const std::vector<Detection>& found) {
  std::vector<double> errors;
  for (const TruthObject& t : Truth()) {
    double best = 0.5;
    for (const Detection& d : found)
      if (d.class_name == t.cls) best = std::min(best, MetresApart(d.position, t.at));
    if (best < 0.5) errors.push_back(best);
  }
  std::sort(errors.begin(), errors.end());
  return errors;
}

// The "event: T\ndata: D\n\n" blocks of a growing buffer, as (type, data).
std::vector<std::pair<std::string, nlohmann::json>> ParseEvents(std::string* buffer) {
  std::vector<std::pair<std::string, nlohmann::json>> out;
  size_t end;
  while ((end = buffer->find("\n\n")) != std::string::npos) {
    const std::string block = buffer->substr(0, end);
    buffer->erase(0, end + 2);
    std::string type, data;
    std::stringstream lines(block);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("event: ", 0) == 0) type = line.substr(7);
      if (line.rfind("data: ", 0) == 0) data = line.substr(6);
    }
    if (!type.empty() && !data.empty()) out.emplace_back(type, nlohmann::json::parse(data));
  }
  return out;
}

TEST(LiveMission, ObjectsAndTheEnhancedLayerFollowTheCorrections) {
  testing::TempDir dir;
  const std::string config = (dir / "both.json").string();
  std::ofstream(config) << R"({"layers": "both", "enhance": {"ops": [{"op": "clahe"}]}})";
  const std::string built = (dir / "built.mbtiles").string(), replayed = (dir / "replayed.mbtiles").string();
  std::string log;
  ASSERT_EQ(
      Seamap(Survey().BuildArgs() + kNoise + " --refine-nav --detect --quiet --config " + config + " --out " + built,
             &log),
      0)
      << log;

  testing::ChildProcess replay({testing::SeamapBinary(),
                                "replay",
                                Survey().dir,
                                "--out",
                                replayed,
                                "--config",
                                config,
                                "--refine-nav",
                                "--nav-noise",
                                "0.005",
                                "--nav-drift",
                                "1",
                                "--heading-noise",
                                "0.5",
                                "--detect",
                                "--speed",
                                "0.5",  // half the camera's pace: a live solve on a loaded machine too
                                "--host",
                                "127.0.0.1",
                                "--port",
                                "0",
                                "--quiet",
                                "--exit-when-done"},
                               (dir / "replay.err").string());
  const auto line = replay.WaitForLine("serving http://", seconds(60));
  ASSERT_TRUE(line) << replay.output();
  const int port = testing::PortFromServingLine(*line);

  int enhanced_tiles = 0, live_corrections = 0;
  std::atomic<bool> complete{false};
  std::thread listener([&] {
    httplib::Client events("127.0.0.1", port);
    events.set_read_timeout(120, 0);
    std::string buffer;
    events.Get("/api/events?types=tile,trajectory,progress", [&](const char* data, size_t n) {
      buffer.append(data, n);
      for (auto& [type, json] : ParseEvents(&buffer)) {
        if (type == "tile") enhanced_tiles += json.value("layer", "") == "enhanced";
        if (type == "trajectory" && !json.value("final", true)) ++live_corrections;
        if (type == "progress" && json.value("state", "") == "complete") complete = true;
      }
      return !complete;
    });
  });
  listener.join();
  const std::optional<int> rc = replay.Wait(seconds(300));
  ASSERT_TRUE(rc.has_value()) << replay.output();
  ASSERT_EQ(*rc, 0) << replay.output();
  ASSERT_TRUE(complete) << replay.output();
  const std::string& out = replay.output();

  // The enhanced layer painted again live: a solve's repaint names both layers' tiles. (Their
  // events' order is no proof: the live builder's own commits are flushed with the records.)
  ASSERT_GT(live_corrections, 0) << "no live correction: " << out;
  std::printf("live corrections %d; enhanced tile events %d\n", live_corrections, enhanced_tiles);
  std::stringstream err_text;  // the solves' lines go to stderr
  err_text << std::ifstream((dir / "replay.err").string()).rdbuf();
  const std::string err = err_text.str();
  const size_t solve = err.find("refine live: solve ");
  ASSERT_NE(solve, std::string::npos) << out << err;
  size_t raw_tiles = 0, enhanced_repainted = 0;
  const size_t counts = err.find(" frames moved more than a pixel painted again (", solve);
  ASSERT_NE(counts, std::string::npos) << err;
  ASSERT_EQ(std::sscanf(err.c_str() + counts, " frames moved more than a pixel painted again (%zu tiles, enhanced %zu)",
                        &raw_tiles, &enhanced_repainted),
            2)
      << err.substr(solve, 400);
  EXPECT_GT(raw_tiles, 0u);
  EXPECT_EQ(enhanced_repainted, raw_tiles);

  // The objects: where the refined map shows them, as build --refine-nav --detect finds them.
  const std::vector<Detection> by_replay = Recognised(replayed), by_build = Recognised(built);
  const std::vector<double> replay_m = ErrorsM(by_replay), build_m = ErrorsM(by_build);
  const size_t truth = Truth().size();
  ASSERT_EQ(build_m.size(), truth) << by_build.size() << " objects found by build";
  ASSERT_EQ(replay_m.size(), truth) << by_replay.size() << " objects found by the replay\n" << out;
  std::printf("objects against the truth: replay median %.1f mm, worst %.1f mm; build median %.1f mm, worst %.1f mm\n",
              1000 * replay_m[truth / 2], 1000 * replay_m.back(), 1000 * build_m[truth / 2], 1000 * build_m.back());
  EXPECT_LE(replay_m.back(), build_m.back() + 0.005);
  // The 2.2 m pipe is placed from its whole box at the coarser level (1.4 cm
  // pixels; measured 66 mm), the others from their own boxes (median 21 mm).
  EXPECT_LT(replay_m[truth / 2], 0.04);
  EXPECT_LT(replay_m.back(), 0.1);
  ASSERT_EQ(by_replay.size(), by_build.size());
  for (size_t i = 0; i < by_build.size(); ++i) {
    double nearest = 1e9;
    for (const Detection& d : by_replay)
      if (d.class_name == by_build[i].class_name)
        nearest = std::min(nearest, MetresApart(d.position, by_build[i].position));
    EXPECT_LT(nearest, 0.005) << by_build[i].class_name;
  }
}

// replay --terrain: the seabed estimated at the end of the dive from the
// photos at the poses they were painted with, the map painted again onto it:
// build --terrain's map, tile for tile, and its height model in the mission.
// The survey is seabed_terrain_test's (the same name and options: simulated once).
TEST(LiveMission, ReplayTerrainLeavesBuildTerrainsMap) {
  const testing::SimulatedSurvey& survey =
      testing::SharedSurvey("relief_dem",
                            "--frames 120 --line-length 5 --line-spacing 0.9 --relief 0.3 --altitude-min 2 "
                            "--altitude-max 2 --width 348 --height 260 --focal-mm 4 --image-format jpg "
                            "--seed 5 --quiet");
  testing::TempDir dir;
  const std::string built = (dir / "built.mbtiles").string(), replayed = (dir / "replayed.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --terrain --quiet --out " + built, &log), 0) << log;
  ASSERT_EQ(Seamap("replay " + survey.dir + " --terrain --speed max --host 127.0.0.1 --port 0 --quiet " +
                       "--exit-when-done --out " + replayed,
                   &log),
            0)
      << log;
  EXPECT_NE(log.find("replay complete"), std::string::npos) << log;

  MBTilesStore a(built, MBTilesStore::Mode::kReadOnly), b(replayed, MBTilesStore::Mode::kReadOnly);
  const int base_zoom = std::stoi(a.Metadata().at("maxzoom"));
  int tiles = 0, differing = 0;
  for (const TileId& id : a.TileIds()) {
    if (id.z != base_zoom) continue;
    ++tiles;
    const auto other = b.GetTile(id);
    ASSERT_TRUE(other) << "tile " << id.z << "/" << id.x << "/" << id.y << " missing from the replay";
    differing += *other != *a.GetTile(id);
  }
  std::printf("replay --terrain: %d of %d base tiles differ from build --terrain's\n", differing, tiles);
  EXPECT_GT(tiles, 10);
  EXPECT_EQ(differing, 0);
  // The height model is the mission's, as build stores it.
  const auto ta = a.Records().Terrain(), tb = b.Records().Terrain();
  ASSERT_TRUE(ta.has_value());
  ASSERT_TRUE(tb.has_value()) << "replay --terrain stored no height model";
  EXPECT_EQ(ta->cells, tb->cells);
  ASSERT_EQ(Seamap("info " + replayed, &log), 0) << log;
  EXPECT_NE(log.find("height model"), std::string::npos) << log;
}

// Options that cannot work are refused before the map is made, naming them.
TEST(LiveMission, ReplayOptionsThatDoNotFitAreRefused) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  const std::string base = "replay " + Survey().dir + " --speed max --exit-when-done --quiet --out " + map;
  std::string log;
  EXPECT_EQ(Seamap(base + " --dem-cell 0.2", &log), 2);
  EXPECT_NE(log.find("--dem-cell: applies to the height model --terrain estimates"), std::string::npos) << log;
  EXPECT_EQ(Seamap(base + " --terrain --terrain-file " + map, &log), 2);
  EXPECT_NE(log.find("--terrain-file"), std::string::npos) << log;
  EXPECT_EQ(Seamap(base + " --refine-nav --refine-features-mb -3", &log), 2);
  EXPECT_NE(log.find("--refine-features-mb"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(map));
}

}  // namespace
}  // namespace seamap
