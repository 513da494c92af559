// Crash-safe builds end to end: `seamap build` killed with SIGKILL at random
// points (after a checkpoint), resumed each time with --resume, ends with the
// tiles of a build that never stopped; the file passes PRAGMA integrity_check
// after every kill and `seamap info` says how to go on. --append skips the
// frames already in a map, and a failed --append leaves its state alone.
#include <signal.h>
#include <sqlite3.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;
using testing::SimulatedSurvey;
using namespace std::chrono_literals;

// 60 frames on lines of 5 m: the look-ahead keeps tiles for the next line.
constexpr int kFrames = 60;
const SimulatedSurvey& Survey() {
  return SharedSurvey("resume", "--frames 60 --line-length 5 --image-format jpg --seed 11");
}

// A checkpoint at every batch of 5 frames, so a kill finds several.
std::string Config(const testing::TempDir& dir) {
  return testing::WriteFile(dir / "often.json",
                            R"({"batch_frames": 5, "batch_seconds": 0, "checkpoint_seconds": 1e-9})")
      .string();
}

std::vector<std::string> BuildArgv(const SimulatedSurvey& s, const std::string& config, const std::string& out) {
  return {testing::SeamapBinary(),
          "build",
          "--images",
          s.photo,
          "--nav",
          s.nav,
          "--camera",
          s.camera,
          "--origin",
          s.origin,
          "--quiet",
          "--config",
          config,
          "--out",
          out};
}

std::string Joined(const std::vector<std::string>& argv) {
  std::string out;
  for (size_t i = 1; i < argv.size(); ++i) out += (i > 1 ? " " : "") + argv[i];
  return out;
}

std::string IntegrityCheck(const std::string& path) {
  sqlite3* db = nullptr;
  std::string result = "cannot open";
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &s, nullptr) == SQLITE_OK && sqlite3_step(s) == SQLITE_ROW)
      result = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  return result;
}

// The frame index of the map's last checkpoint, -1 before the first (or no map yet).
int CheckpointedFrame(const std::string& path) {
  try {
    MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
    auto c = store.ReadCheckpoint();
    return c ? nlohmann::json::parse(c->progress).value("frame_index", -1) : -1;
  } catch (const std::exception&) {
    return -1;
  }
}

std::string State(const std::string& path) {
  MBTilesStore store(path, MBTilesStore::Mode::kReadOnly);
  auto meta = store.Metadata();
  return meta.count("seamap_state") ? meta["seamap_state"] : "";
}

TEST(Resume, KilledBuildsResumeToTheTilesOfAnUninterruptedBuild) {
  const SimulatedSurvey& survey = Survey();
  testing::TempDir dir;
  const std::string config = Config(dir);
  const std::string reference = (dir / "reference.mbtiles").string(), map = (dir / "killed.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(Joined(BuildArgv(survey, config, reference)), &log), 0) << log;

  const char* fixed = std::getenv("SEAMAP_RESUME_SEED");
  const unsigned seed = fixed ? static_cast<unsigned>(std::atoi(fixed)) : std::random_device{}();
  std::cout << "resume test seed " << seed << " (SEAMAP_RESUME_SEED=" << seed << " repeats it)\n";
  RecordProperty("seed", static_cast<int>(seed));
  std::mt19937 rng(seed);
  // Kill points: checkpointed frames to wait for, then a random moment after.
  std::vector<int> targets;
  for (int i = 0; i < 4; ++i) targets.push_back(std::uniform_int_distribution<int>(4, kFrames - 8)(rng));
  std::sort(targets.begin(), targets.end());

  int kills = 0;
  bool resume = false;
  std::string resume_command;  // as `seamap info` says it
  for (int target : targets) {
    std::vector<std::string> argv = BuildArgv(survey, config, map);
    if (resume) argv.push_back("--resume");
    testing::ChildProcess build(argv, (dir / "build.err").string());
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    std::optional<int> ended;
    while (CheckpointedFrame(map) < target && !(ended = build.Wait(0s)) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(10ms);
    if (ended) break;  // finished before this point: nothing left to kill
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 60)(rng)));
    build.Signal(SIGKILL);
    ended = build.Wait(30s);
    resume = true;
    if (ended && *ended == 0) break;  // it won the race
    ++kills;
    SCOPED_TRACE("killed after checkpoint " + std::to_string(target));
    EXPECT_EQ(IntegrityCheck(map), "ok");
    EXPECT_EQ(State(map), "building");
    ASSERT_EQ(Seamap("info " + map, &log), 0) << log;
    EXPECT_NE(log.find("state:     interrupted"), std::string::npos) << log;
    // The exact command: the interrupted build's own arguments, then --resume.
    const std::string again = "seamap " + Joined(BuildArgv(survey, config, map)) + " --resume";
    EXPECT_NE(log.find(again), std::string::npos) << log;
    resume_command = log.substr(log.find("Resume with: ") + 13);
    resume_command = resume_command.substr(0, resume_command.find('\n'));
    if (kills == 1) {  // the server says the same
      testing::ChildProcess serve(
          {testing::SeamapBinary(), "serve", map, "--read-only", "--host", "127.0.0.1", "--port", "0"});
      auto line = serve.WaitForLine("serving http://", 30s);
      ASSERT_TRUE(line) << serve.output();
      httplib::Client api("127.0.0.1", testing::PortFromServingLine(*line));
      auto res = api.Get("/api/status");
      ASSERT_TRUE(res);
      const nlohmann::json status = nlohmann::json::parse(res->body);
      EXPECT_EQ(status["state"], "interrupted");
      EXPECT_NE(status["state_detail"].get<std::string>().find(again), std::string::npos) << status.dump();
      serve.Signal(SIGTERM);
      EXPECT_EQ(serve.Wait(30s), 0);
    }
  }
  std::cout << "killed " << kills << " times\n";
  EXPECT_GE(kills, 1);
  if (resume) {  // the command `seamap info` gave, word for word (with this checkout's binary)
    const size_t at = resume_command.find("&& seamap build ");
    ASSERT_NE(at, std::string::npos) << resume_command;
    resume_command.replace(at, 16, "&& " + testing::SeamapBinary() + " build ");
    ASSERT_EQ(testing::RunCommand(resume_command, &log), 0) << resume_command << "\n" << log;
  } else {
    ASSERT_EQ(Seamap(Joined(BuildArgv(survey, config, map)), &log), 0) << log;
  }
  EXPECT_EQ(IntegrityCheck(map), "ok");

  MBTilesStore a(reference, MBTilesStore::Mode::kReadOnly), b(map, MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(b.Metadata().at("seamap_state"), "complete");
  EXPECT_FALSE(b.ReadCheckpoint()) << "a finished build forgets its checkpoint";
  std::vector<TileId> ids = a.TileIds(), other = b.TileIds();
  std::sort(ids.begin(), ids.end());
  std::sort(other.begin(), other.end());
  ASSERT_EQ(ids, other);
  int differ = 0;
  for (const TileId& id : ids) differ += *a.GetTile(id) != *b.GetTile(id);
  EXPECT_EQ(differ, 0) << "of " << ids.size() << " tiles";  // pixel-equal: the same bytes

  const auto frames = b.Frames();
  std::set<std::string> images;
  for (const auto& f : frames) images.insert(f.image);
  EXPECT_EQ(frames.size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(images.size(), frames.size()) << "an image is in the frames table twice";
  const auto track = b.Track();
  std::set<int> seqs;
  std::set<double> times;
  for (const auto& p : track) {
    seqs.insert(p.seq);
    if (p.time_s) times.insert(*p.time_s);
  }
  EXPECT_EQ(track.size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(seqs.size(), track.size());
  EXPECT_EQ(times.size(), track.size());
  for (const char* key : {"bounds", "seamap_frames_used", "minzoom", "maxzoom"})
    EXPECT_EQ(a.Metadata().at(key), b.Metadata().at(key)) << key;
}

TEST(Resume, AppendSkipsFramesInTheMapAndAFailedAppendKeepsItsState) {
  const SimulatedSurvey& survey = Survey();
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  // The first 40 frames, then the whole survey appended: 40 skipped, 20 added.
  std::ifstream in(survey.nav);
  std::ofstream first((dir / "first.csv").string());
  std::string line;
  for (int i = 0; i <= 40 && std::getline(in, line); ++i) first << line << "\n";
  first.close();
  const std::string common =
      "build --images " + survey.photo + " --camera " + survey.camera + " --origin " + survey.origin + " --quiet";
  std::string log;
  ASSERT_EQ(Seamap(common + " --out " + map + " --nav " + (dir / "first.csv").string(), &log), 0) << log;
  ASSERT_EQ(Seamap(common + " --out " + map + " --nav " + survey.nav + " --append", &log), 0) << log;
  EXPECT_NE(log.find("40 frames are in the map already and are skipped (frame_000000.jpg"), std::string::npos) << log;
  EXPECT_NE(log.find("frames used 20, rejected 0; tiles written"), std::string::npos) << log;
  EXPECT_NE(log.find("; 40 already in the map, skipped"), std::string::npos) << log;
  {
    MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
    const auto frames = store.Frames();
    ASSERT_EQ(frames.size(), static_cast<size_t>(kFrames));
    EXPECT_EQ(frames.back().id, kFrames - 1);
    std::set<std::string> images;
    for (const auto& f : frames) images.insert(f.image);
    EXPECT_EQ(images.size(), frames.size()) << "an image is in the frames table twice";
    EXPECT_EQ(store.Track().size(), static_cast<size_t>(kFrames));
    EXPECT_EQ(store.Metadata().at("seamap_state"), "complete");
  }
  const int64_t tiles = MBTilesStore(map, MBTilesStore::Mode::kReadOnly).TileCount();

  // The same survey again adds nothing and changes nothing.
  ASSERT_EQ(Seamap(common + " --out " + map + " --nav " + survey.nav + " --append", &log), 0) << log;
  EXPECT_NE(log.find("nothing to add"), std::string::npos) << log;
  EXPECT_EQ(MBTilesStore(map, MBTilesStore::Mode::kReadOnly).Frames().size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(State(map), "complete");

  // A bad camera fails the append; the map stays complete.
  const std::string bad = testing::WriteFile(dir / "bad_camera.json", "{\"width\": \"wide\"}").string();
  const std::string with_bad = "build --images " + survey.photo + " --camera " + bad + " --origin " + survey.origin +
                               " --quiet --out " + map + " --nav " + survey.nav + " --append";
  EXPECT_NE(Seamap(with_bad, &log), 0) << log;
  EXPECT_NE(log.find(bad), std::string::npos) << log;
  EXPECT_EQ(State(map), "complete");
  EXPECT_EQ(MBTilesStore(map, MBTilesStore::Mode::kReadOnly).TileCount(), tiles);
  ASSERT_EQ(Seamap("info " + map, &log), 0) << log;
  EXPECT_NE(log.find("state:     complete"), std::string::npos) << log;

  // Nothing to resume in a complete map; a folder keeps no checkpoints.
  EXPECT_EQ(Seamap(common + " --out " + map + " --nav " + survey.nav + " --resume", &log), 2);
  EXPECT_NE(log.find("--resume"), std::string::npos) << log;
  EXPECT_NE(log.find("is complete"), std::string::npos) << log;
  const std::string folder = (dir / "tiles").string();
  ASSERT_EQ(Seamap(common + " --nav " + (dir / "first.csv").string() + " --out " + folder, &log), 0) << log;
  EXPECT_EQ(Seamap(common + " --nav " + survey.nav + " --out " + folder + " --resume", &log), 2);
  EXPECT_NE(log.find("tile folder keeps no checkpoints"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
