// The recogniser end to end: build --detect against seamap detect on the
// finished map, stable ids on a second run, bad models and options refused
// before any tile is read, and recall of the shipped model on a simulated
// survey with objects.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap {
namespace {

using testing::Seamap;
namespace fs = std::filesystem;

const std::string kFixtures = std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/";
const std::string kV8 = kFixtures + "yolo_v8_fixture.onnx";

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("detect", "--frames 40 --line-length 3 --seed 3");
}

std::vector<Detection> Recognised(const std::string& map) {
  std::vector<Detection> out;
  for (const Detection& d : OpenExistingMap(map, false)->Records().Detections())
    if (d.source == "recogniser") out.push_back(d);
  std::sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) {
    return std::make_tuple(a.class_name, a.position.lat, a.position.lon) <
           std::make_tuple(b.class_name, b.position.lat, b.position.lon);
  });
  return out;
}

double MetresApart(LatLon a, LatLon b) {
  const LocalFrame f(a);
  const LocalXY d = f.FromLatLon(b);
  return std::hypot(d.east, d.north);
}

// The fixture model answers every window with the same two boxes, so the
// detections say exactly which windows were searched, skipped and merged.
TEST(Detect, BuildDetectEqualsDetectOnTheFinishedMap) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("build --quiet " + Survey().BuildArgs() + " --out " + map + " --detect --detect-model " + kV8, &out),
            0)
      << out;
  EXPECT_NE(out.find("ms per window"), std::string::npos) << out;
  const std::vector<Detection> live = Recognised(map);
  ASSERT_GE(live.size(), 4u);
  const std::string geojson = (dir / "d.geojson").string();
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + kV8 + " --threads 2 --out " + geojson, &out), 0) << out;
  EXPECT_NE(out.find("crate"), std::string::npos) << out;
  const std::vector<Detection> offline = Recognised(map);
  ASSERT_EQ(offline.size(), live.size());
  for (size_t i = 0; i < live.size(); ++i) {
    EXPECT_EQ(offline[i].class_name, live[i].class_name);
    EXPECT_LT(MetresApart(offline[i].position, live[i].position), 0.001);
    EXPECT_EQ(offline[i].id, live[i].id);  // the second run updates, never duplicates
  }
  std::ifstream in(geojson);
  const auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["features"].size(), live.size());
  const auto& p = j["features"][0]["properties"];
  EXPECT_EQ(p["source"], "recogniser");
  EXPECT_EQ(p["box"][0].size(), 5u);
  EXPECT_EQ(p["model"].get<std::string>().rfind("yolo_v8_fixture.onnx#", 0), 0u);
  int with_frames = 0;
  for (const auto& f : j["features"]) with_frames += !f["properties"]["frames"].empty();
  EXPECT_GT(with_frames, 0);
}

// A live replay shows half-painted tiles; its detections still equal detect's on the finished map.
TEST(Detect, ReplayDetectEqualsDetectOnTheFinishedMap) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("replay " + Survey().dir + " --out " + map +
                       " --speed max --host 127.0.0.1 --port 0 --quiet --exit-when-done --web " + SEAMAP_SOURCE_DIR +
                       "/web --detect --detect-model " + kV8,
                   &out),
            0)
      << out;
  EXPECT_NE(out.find("detect: "), std::string::npos) << out;
  const std::vector<Detection> live = Recognised(map);
  ASSERT_GE(live.size(), 4u);
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + kV8, &out), 0) << out;
  const std::vector<Detection> offline = Recognised(map);
  ASSERT_EQ(offline.size(), live.size());
  for (size_t i = 0; i < live.size(); ++i) {
    EXPECT_EQ(offline[i].class_name, live[i].class_name);
    EXPECT_LT(MetresApart(offline[i].position, live[i].position), 0.001);
  }
}

// replay --detect: objects reach the console as they are found, as SSE
// `detection` events while the map still grows, not only at the end.
TEST(Detect, ReplayDetectAnnouncesObjectsWhileTheMapGrows) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  testing::ChildProcess replay(
      {testing::SeamapBinary(), "replay", Survey().dir, "--out", map, "--speed", "1", "--host", "127.0.0.1", "--port",
       "0", "--quiet", "--web", std::string(SEAMAP_SOURCE_DIR) + "/web", "--detect", "--detect-model", kV8},
      (dir / "replay.err").string());
  const auto line = replay.WaitForLine("serving http://", std::chrono::seconds(60));
  ASSERT_TRUE(line) << replay.output();
  const int port = testing::PortFromServingLine(*line);
  int before_complete = 0;
  std::atomic<bool> complete{false};
  std::thread listener([&] {
    httplib::Client events("127.0.0.1", port);
    events.set_read_timeout(60, 0);
    std::string buffer;
    events.Get("/api/events?types=detection,progress", [&](const char* data, size_t n) {
      buffer.append(data, n);
      for (size_t end; (end = buffer.find("\n\n")) != std::string::npos; buffer.erase(0, end + 2)) {
        const std::string block = buffer.substr(0, end);
        if (block.find("event: detection") != std::string::npos && !complete) ++before_complete;
        if (block.find("event: progress") != std::string::npos &&
            block.find("\"state\":\"complete\"") != std::string::npos)
          complete = true;
      }
      return !complete;
    });
  });
  listener.join();
  EXPECT_TRUE(complete) << "the replay never said complete";
  EXPECT_GT(before_complete, 0) << "no detection event while the map was growing";
  httplib::Client api("127.0.0.1", port);
  auto res = api.Get("/api/detections?source=recogniser");
  ASSERT_TRUE(res);
  const auto served = nlohmann::json::parse(res->body)["features"];
  EXPECT_EQ(served.size(), Recognised(map).size());
  EXPECT_GE(served.size(), 4u);
}

// Exit 2 and the message names `what`.
void ExpectRefused(const std::string& args, const std::string& what) {
  std::string out;
  EXPECT_EQ(Seamap(args, &out), 2) << args << "\n" << out;
  EXPECT_NE(out.find(what), std::string::npos) << args << "\n" << out;
}

TEST(Detect, BadModelsClassesAndOptionsAreRefusedNamingThem) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("build --quiet " + Survey().BuildArgs() + " --out " + map, &out), 0) << out;
  const std::string text = testing::WriteFile(dir / "model.onnx", "not a model\n").string();
  ExpectRefused("detect " + map + " --model " + text, "model.onnx: not an ONNX model");
  ExpectRefused("detect " + map + " --model " + kFixtures + "yolo_bad_output_fixture.onnx", "[1, 10]");
  const std::string three = testing::WriteFile(dir / "three.txt", "tyre\ncrate\npipe\n").string();
  ExpectRefused("detect " + map + " --model " + kV8 + " --classes " + three, "three.txt");
  ExpectRefused("detect " + map + " --model " + kV8 + " --layer enhanced", "--layer");
  ExpectRefused("detect " + map + " --model " + kV8 + " --zooms 12", "--zooms");
  ExpectRefused("detect " + map + " --model " + kV8 + " --min-score 2", "--min-score");
  // The model is checked before the map is opened: a bad model and no map name the model.
  ExpectRefused("detect " + (dir / "none.mbtiles").string() + " --model " + text, "model.onnx");
  ExpectRefused("build --quiet " + Survey().BuildArgs() + " --out " + (dir / "b.mbtiles").string() +
                    " --detect --detect-model " + text,
                "model.onnx: not an ONNX model");
  EXPECT_FALSE(fs::exists(dir / "b.mbtiles"));
  const std::string config = testing::WriteFile(dir / "c.json", R"({"detect": {"zooms": [12]}})").string();
  ExpectRefused("build --quiet " + Survey().BuildArgs() + " --config " + config + " --out " +
                    (dir / "c.mbtiles").string() + " --detect --detect-model " + kV8,
                "detect.zooms");
  EXPECT_TRUE(Recognised(map).empty());  // nothing was stored by the refused runs
}

// The shipped model on a survey with objects (spec sect. 12, 10 cm rule).
TEST(Detect, ShippedModelFindsSimulatedObjects) {
  const std::string model = std::string(SEAMAP_SOURCE_DIR) + "/data/models/seabed_objects.onnx";
  if (!fs::exists(model)) GTEST_SKIP() << "no shipped model at " << model;
  const auto& survey = testing::SharedSurvey("detect_objects", "--objects 10 --seed 5");
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("build --quiet " + survey.BuildArgs() + " --out " + map + " --detect", &out), 0) << out;
  const std::vector<Detection> found = Recognised(map);
  struct Truth {
    std::string cls;
    LatLon ll;
  };
  std::vector<Truth> truth;
  std::ifstream in(survey.dir + "/truth/objects.csv");
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "class,lat,lon,x_m,y_m,size_m");
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    Truth t;
    std::string lat, lon;
    std::getline(ss, t.cls, ',');
    std::getline(ss, lat, ',');
    std::getline(ss, lon, ',');
    t.ll = {std::stod(lat), std::stod(lon)};
    truth.push_back(t);
  }
  ASSERT_EQ(truth.size(), 10u);
  // Greedy one-to-one matching of same-class pairs within 10 cm, nearest first.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < found.size(); ++i)
    for (size_t k = 0; k < truth.size(); ++k)
      if (found[i].class_name == truth[k].cls) {
        const double d = MetresApart(found[i].position, truth[k].ll);
        if (d <= 0.10) pairs.emplace_back(d, i, k);
      }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> used_found(found.size()), used_truth(truth.size());
  std::vector<double> errors_m;
  for (const auto& [d, i, k] : pairs)
    if (!used_found[i] && !used_truth[k]) used_found[i] = used_truth[k] = true, errors_m.push_back(d);
  // The issue's targets (recall and precision >= 0.9, median error <= 5 cm) on a survey training never saw
  // (seed 5; training used 1000-1035). Today's model finds all 10 with 10 detections (data/models/README.md).
  const size_t matched = errors_m.size();
  EXPECT_GE(matched, 9u) << found.size() << " detections\n" << out;
  EXPECT_GE(static_cast<double>(matched) / std::max<size_t>(found.size(), 1), 0.9) << "precision";
  ASSERT_FALSE(errors_m.empty());
  EXPECT_LE(errors_m[(errors_m.size() - 1) / 2], 0.05) << "median position error (pairs sorted nearest first)";
  // And the same detections as seamap detect on the finished map.
  ASSERT_EQ(Seamap("detect --quiet " + map, &out), 0) << out;
  const std::vector<Detection> offline = Recognised(map);
  ASSERT_EQ(offline.size(), found.size());
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_EQ(offline[i].class_name, found[i].class_name);
    EXPECT_LT(MetresApart(offline[i].position, found[i].position), 0.001);
  }
}

}  // namespace
}  // namespace seamap
