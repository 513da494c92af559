// Stereo in the dive: `stereo-locate --pairs DIR` with a trajectory and no
// --time locates every pair on its own at its own time (from its name or
// --pair-times), places it on the trajectory (the mission's own with --map),
// skips a pair outside the trajectory's times, and stores one object.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/mission_metadata.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

// The scene's navigation drifted this far north: what the mission's refined trajectory corrected.
constexpr double kDriftNorthM = 0.4;

struct Dive {
  std::unique_ptr<testing::TempDir> dir;
  std::string root, calib, model, pairs, nav;
  nlohmann::json truth;
};

// One scene, its model (two overview pairs) and a dive of 5 sightings and a pair after the navigation
// ends, per test binary (one sample per pixel: quick).
const Dive& SharedDive() {
  static Dive dive = [] {
    Dive d;
    d.dir = std::make_unique<testing::TempDir>();
    d.root = (d.dir->path() / "scene").string();
    d.calib = d.root + "/stereo.yaml";
    d.model = (d.dir->path() / "object.json").string();
    d.pairs = d.root + "/dive";
    d.nav = d.root + "/dive/nav.csv";
    std::string log;
    if (Seamap("simulate-stereo --out " + d.root + " --seed 2 --views 2 --dive 5 --supersample 1", &log) != 0)
      ADD_FAILURE() << "simulate-stereo failed:\n" << log;
    if (Seamap("stereo-model --calib " + d.calib + " --pairs " + d.root + "/overview --out " + d.model, &log) != 0)
      ADD_FAILURE() << "stereo-model failed:\n" << log;
    d.truth = nlohmann::json::parse(std::ifstream(d.root + "/truth/dive.json"));
    return d;
  }();
  return dive;
}

struct NavRow {
  double time_s, lat, lon, depth_m, altitude_m, heading_deg;
};

std::vector<NavRow> ReadNav(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<NavRow> rows;
  NavRow r{};
  char c;
  double pitch, roll;
  while (in >> r.time_s >> c >> r.lat >> c >> r.lon >> c >> r.depth_m >> c >> r.altitude_m >> c >> r.heading_deg >> c >>
         pitch >> c >> roll)
    rows.push_back(r);
  return rows;
}

// A mission as `build --refine-nav` leaves it: frames placed on the true (refined) trajectory,
// the drifting navigation's poses beside them.
void MakeRefinedMission(const Dive& d, const std::string& path) {
  MBTilesStore store(path, MBTilesStore::Mode::kCreate);
  const LatLon origin{d.truth["origin"][0].get<double>(), d.truth["origin"][1].get<double>()};
  const LocalFrame frame(origin);
  int id = 0;
  for (const NavRow& r : ReadNav(d.nav)) {
    FrameRecord f;
    f.id = id;
    f.image = "frame_" + std::to_string(id++) + ".png";
    f.time_s = r.time_s;
    f.position = {r.lat, r.lon};
    f.depth_m = r.depth_m, f.altitude_m = r.altitude_m, f.heading_deg = r.heading_deg;
    f.status = "used";
    LocalXY xy = frame.FromLatLon(f.position);
    xy.north += kDriftNorthM;
    f.nav = NavigatedPose{frame.ToLatLon(xy), r.altitude_m, r.depth_m, r.heading_deg, 0, 0};
    store.Records().PutFrame(f);
  }
  store.SetMetadata("name", "dive");
  store.SetMetadata("format", "png");
  MissionMetadata m;
  m.origin = origin;
  m.trajectory = nlohmann::json{{"mode", "refine"}};
  m.state = "complete";
  WriteMissionMetadata(&store, m);
  store.Flush();
}

nlohmann::json Locate(const Dive& d, const std::string& extra, std::string* log) {
  const std::string out = (d.dir->path() / "sightings.json").string();
  std::filesystem::remove(out);
  EXPECT_EQ(Seamap("stereo-locate --calib " + d.calib + " --model " + d.model + " --pairs " + d.pairs + " --out " +
                       out + " --rig down --quiet " + extra,
                   log),
            0)
      << *log;
  std::printf("%s", log->c_str());
  return nlohmann::json::parse(std::ifstream(out));
}

// Every sighting in the navigation's times found and placed within `tolerance_m` of the truth;
// the pair after the navigation's end skipped. Returns the worst horizontal error.
double CheckSightings(const Dive& d, const nlohmann::json& out, double tolerance_m) {
  const nlohmann::json& object = d.truth["object"];
  const LocalFrame frame({d.truth["origin"][0].get<double>(), d.truth["origin"][1].get<double>()});
  const LocalXY truth = frame.FromLatLon({object["lat"].get<double>(), object["lon"].get<double>()});
  EXPECT_EQ(out["format"], "seamap-stereo-sightings");
  const nlohmann::json& sightings = out["sightings"];
  EXPECT_EQ(sightings.size(), d.truth["sightings"].size());
  double worst = 0;
  for (size_t i = 0; i < sightings.size() && i < d.truth["sightings"].size(); ++i) {
    const nlohmann::json& s = sightings[i];
    const nlohmann::json& t = d.truth["sightings"][i];
    EXPECT_EQ(s["pair"], t["pair"]);
    EXPECT_NEAR(s["time_s"].get<double>(), t["time_s"].get<double>(), 1e-9);
    if (!t["in_navigation"].get<bool>()) {
      EXPECT_FALSE(s["found"].get<bool>());
      EXPECT_NE(s.value("skipped", "").find("outside the trajectory's times"), std::string::npos) << s.dump();
      continue;
    }
    EXPECT_TRUE(s["found"].get<bool>()) << s.dump();
    if (!s.contains("geo")) {
      ADD_FAILURE() << "not placed: " << s.dump();
      continue;
    }
    const LocalXY at = frame.FromLatLon({s["geo"]["lat"].get<double>(), s["geo"]["lon"].get<double>()});
    const double error = std::hypot(at.east - truth.east, at.north - truth.north);
    worst = std::max(worst, error);
    EXPECT_LT(error, tolerance_m) << s["pair"];
    EXPECT_NEAR(s["geo"]["depth_m"].get<double>(), object["depth_m"].get<double>(), tolerance_m) << s["pair"];
    EXPECT_LT(
        std::abs(std::remainder(s["geo"]["heading_deg"].get<double>() - object["heading_deg"].get<double>(), 360.0)),
        0.5)
        << s["pair"];
    EXPECT_GT(s["uncertainty"]["point_sigma_m"].get<double>(), 0);  // the stereo's own uncertainty, as pose.json has it
  }
  const nlohmann::json& summary = out["summary"];
  EXPECT_EQ(summary["pairs"], 6);
  EXPECT_EQ(summary["found"], 5);
  EXPECT_EQ(summary["skipped"], 1);
  EXPECT_EQ(summary["not_found"], 0);
  EXPECT_EQ(summary["objects"].size(), 1u);
  if (!summary["objects"].empty()) {
    EXPECT_EQ(summary["objects"][0]["sightings"], 5);
    EXPECT_LT(summary["objects"][0]["spread_max_m"].get<double>(), tolerance_m);
  }
  return worst;
}

// The stereo's own error: the object frame's origin sits 3.6 m above the object, so a sighting's
// ~0.5 mrad rotation error moves it ~2 mm (docs/STEREO.md); with the exact trajectory, 1 cm bounds it.
constexpr double kExactToleranceM = 0.01;

TEST(StereoDive, EverySightingOnTheNavigationIsFoundAndPlacedAndPairsWithoutATimeAreRefused) {
  const Dive& d = SharedDive();
  std::string log;
  const nlohmann::json out = Locate(d, "--nav " + d.nav, &log);
  const double worst = CheckSightings(d, out, kExactToleranceM);
  std::printf("dive on the exact navigation: worst sighting %.1f mm from the truth\n", 1000 * worst);
  EXPECT_NE(log.find("5 found, 0 not found, 1 outside the trajectory's times"), std::string::npos) << log;

  // A pair must have a time, a table must give it, and a dive locates pairs one by one.
  const std::string base = "stereo-locate --calib " + d.calib + " --model " + d.model + " --out " +
                           (d.dir->path() / "x.json").string() + " --quiet";
  // Pairs named by a counter (ap_001) have no time.
  EXPECT_EQ(Seamap(base + " --pairs " + d.root + "/approach --nav " + d.nav, &log), 2) << log;
  EXPECT_NE(log.find("--pair-times"), std::string::npos) << log;
  EXPECT_NE(log.find("ap_001"), std::string::npos) << log;
  // A table without the pair, or with a time that is not one.
  const std::string partial = (d.dir->path() / "partial.csv").string();
  std::ofstream(partial) << "image,time_s\n" << d.truth["sightings"][0]["pair"].get<std::string>() << ",12.5\n";
  EXPECT_EQ(Seamap(base + " --pairs " + d.pairs + " --nav " + d.nav + " --pair-times " + partial, &log), 2) << log;
  EXPECT_NE(log.find("has no time for pair"), std::string::npos) << log;
  const std::string bad = (d.dir->path() / "bad.csv").string();
  std::ofstream(bad) << "image,time_s\nx,soon\n";
  EXPECT_EQ(Seamap(base + " --pairs " + d.pairs + " --nav " + d.nav + " --pair-times " + bad, &log), 2) << log;
  EXPECT_NE(log.find("bad.csv:2"), std::string::npos) << log;
  EXPECT_NE(log.find("soon"), std::string::npos) << log;
  // A dive locates pairs one by one; joint views go with --time.
  EXPECT_EQ(Seamap(base + " --pairs " + d.pairs + " --nav " + d.nav + " --views 2", &log), 2) << log;
  EXPECT_NE(log.find("--views"), std::string::npos) << log;
}

TEST(StereoDive, TheMissionsRefinedTrajectoryPlacesThemNotItsNavigation) {
  const Dive& d = SharedDive();
  const std::string map = (d.dir->path() / "refined.mbtiles").string();
  MakeRefinedMission(d, map);
  // Each pair's time from a table naming the pairs by their left image (the same times as their names give).
  const std::string times = (d.dir->path() / "times.csv").string();
  {
    std::ofstream csv(times);
    csv << "image,time_s\n";
    for (const auto& s : d.truth["sightings"])
      csv << s["pair"].get<std::string>() << "_left.png," << s["time_s"].get<double>() << "\n";
  }
  std::string log;
  const nlohmann::json out = Locate(d, "--map " + map + " --pair-times " + times, &log);
  EXPECT_EQ(out["sightings"][0]["time_from"], "--pair-times");
  EXPECT_NE(out["trajectory"].get<std::string>().find("refined"), std::string::npos) << out["trajectory"];
  CheckSightings(d, out, kExactToleranceM);
  // One object in the mission, where the sightings agree.
  auto store = OpenExistingMap(map, false);
  std::vector<Detection> stereo;
  for (const Detection& det : store->Records().Detections())
    if (det.source == "stereo") stereo.push_back(det);
  ASSERT_EQ(stereo.size(), 1u);
  const LocalFrame frame({d.truth["origin"][0].get<double>(), d.truth["origin"][1].get<double>()});
  const LocalXY at = frame.FromLatLon(stereo[0].position);
  const LocalXY truth =
      frame.FromLatLon({d.truth["object"]["lat"].get<double>(), d.truth["object"]["lon"].get<double>()});
  EXPECT_LT(std::hypot(at.east - truth.east, at.north - truth.north), kExactToleranceM);
  EXPECT_EQ(stereo[0].class_name, out["model"].get<std::string>());

  // The drifting navigation beside it would have put every sighting 0.4 m north.
  const std::string drifted = (d.dir->path() / "drifted.csv").string();
  {
    std::ofstream csv(drifted);
    csv << "time_s,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg\n";
    for (const NavRow& r : ReadNav(d.nav)) {
      const LocalXY xy = frame.FromLatLon({r.lat, r.lon});
      csv << std::to_string(r.time_s) << "," << xy.east << "," << xy.north + kDriftNorthM << "," << r.depth_m << ","
          << r.altitude_m << "," << r.heading_deg << ",0,0\n";
    }
  }
  const nlohmann::json off = Locate(d, "--nav " + drifted + " --map " + map, &log);
  const nlohmann::json& first = off["sightings"][0];
  ASSERT_TRUE(first["found"].get<bool>());
  const LocalXY moved = frame.FromLatLon({first["geo"]["lat"].get<double>(), first["geo"]["lon"].get<double>()});
  EXPECT_NEAR(moved.north - truth.north, kDriftNorthM, kExactToleranceM);
}

}  // namespace
}  // namespace seamap
