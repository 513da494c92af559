// One trajectory in the mission: `build --refine-nav` and `replay --nav-mode`
// write the poses their frames were placed with (--trajectory-out, in
// `seamap trajectory --out`'s form), and a later stage reads them from the
// mission (stereo-locate --map --time) instead of the navigation.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/mission_trajectory.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

// Two short lines with a drifting navigation: refine has cross-line pairs to correct it with.
const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("mission_trajectory",
                               "--frames 30 --line-length 2.5 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 "
                               "--heading-noise 0.5 --seed 7 --quiet");
}

struct Csv {
  std::string header;
  std::map<std::string, std::vector<std::string>> rows;  // by image
  std::vector<std::string> columns;
};

Csv ReadCsv(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  std::getline(in, csv.header);
  std::stringstream h(csv.header);
  for (std::string c; std::getline(h, c, ',');) csv.columns.push_back(c);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
    if (!fields.empty()) csv.rows[fields[0]] = fields;
  }
  return csv;
}

double Field(const Csv& csv, const std::string& image, const std::string& column) {
  for (size_t i = 0; i < csv.columns.size(); ++i)
    if (csv.columns[i] == column) return std::stod(csv.rows.at(image).at(i));
  ADD_FAILURE() << "no column " << column;
  return NAN;
}

TEST(MissionTrajectory, BuildRefineNavWritesTheRefinedTrajectoryAsSeamapTrajectoryDoes) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string(), mine = (dir / "built.csv").string(),
                    reference = (dir / "trajectory.csv").string();
  std::string log;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --refine-nav --trajectory-out " + mine + " --out " + map, &log), 0) << log;
  EXPECT_NE(log.find("trajectory (refined): 30 frames -> " + mine), std::string::npos) << log;
  ASSERT_EQ(Seamap("trajectory --images " + Survey().photo + " --nav " + Survey().nav + " --camera " + Survey().camera +
                       " --origin " + Survey().origin + " --mode refine --quiet --out " + reference,
                   &log),
            0)
      << log;
  const Csv built = ReadCsv(mine), refined = ReadCsv(reference), nav = ReadCsv(Survey().nav);
  // The same form (the flags column only where a row has flags) and the same poses, to well under a millimetre.
  EXPECT_EQ(built.columns.size() >= 11 ? built.columns[10] : "", "roll_deg");
  EXPECT_EQ(std::vector<std::string>(built.columns.begin(), built.columns.begin() + 11),
            std::vector<std::string>(refined.columns.begin(), refined.columns.begin() + 11));
  ASSERT_EQ(built.rows.size(), 30u);
  ASSERT_EQ(refined.rows.size(), 30u);
  double moved_m = 0;
  for (const auto& [image, row] : refined.rows) {
    ASSERT_TRUE(built.rows.count(image)) << image;
    for (const char* c : {"time_s", "x_m", "y_m", "depth_m", "altitude_m"})
      EXPECT_NEAR(Field(built, image, c), Field(refined, image, c), 1e-4) << image << " " << c;
    EXPECT_NEAR(std::remainder(Field(built, image, "heading_deg") - Field(refined, image, "heading_deg"), 360), 0,
                1e-6);
    moved_m = std::max(moved_m, std::hypot(Field(built, image, "x_m") - Field(nav, image, "x_m"),
                                           Field(built, image, "y_m") - Field(nav, image, "y_m")));
  }
  EXPECT_GT(moved_m, 0.01) << "the refined trajectory should differ from the drifting navigation";

  // The mission says what it holds, and serves it (/api/track?source=refined through MissionTrajectory).
  MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
  const MissionTrajectory held = MissionTrajectory::Read(store);
  EXPECT_EQ(held.placed(), TrajectorySource::kRefined);
  EXPECT_EQ(held.Poses(TrajectorySource::kRefined).size(), 30u);

  // What was written is navigation `seamap build --nav` reads as is.
  const std::string args = Survey().BuildArgs();
  const std::string rebuilt = args.substr(0, args.find(" --nav ")) + " --nav " + mine +
                              args.substr(args.find(" --camera ")) + " --out " + (dir / "again.mbtiles").string();
  EXPECT_EQ(Seamap(rebuilt, &log), 0) << log;
}

TEST(MissionTrajectory, ReplayWritesTheFiltersTrajectory) {
  testing::TempDir dir;
  const std::string map = (dir / "live.mbtiles").string(), out = (dir / "vo.csv").string();
  std::string log;
  ASSERT_EQ(
      Seamap("replay " + Survey().dir + " --out " + map +
                 " --speed max --exit-when-done --quiet --nav-mode vo --host 127.0.0.1 --port 0 --trajectory-out " +
                 out,
             &log),
      0)
      << log;
  EXPECT_NE(log.find("trajectory (estimated): 30 frames -> " + out), std::string::npos) << log;
  const Csv vo = ReadCsv(out), nav = ReadCsv(Survey().nav);
  ASSERT_EQ(vo.rows.size(), 30u);
  // Each row is the pose the mission's frame was placed with, not the navigation's.
  MBTilesStore store(map, MBTilesStore::Mode::kReadOnly);
  int differ = 0;
  for (const FrameRecord& f : store.Records().Frames()) {
    ASSERT_TRUE(vo.rows.count(f.image)) << f.image;
    EXPECT_NEAR(Field(vo, f.image, "lat"), f.position.lat, 1e-9);
    EXPECT_NEAR(Field(vo, f.image, "lon"), f.position.lon, 1e-9);
    differ += std::hypot(Field(vo, f.image, "x_m") - Field(nav, f.image, "x_m"),
                         Field(vo, f.image, "y_m") - Field(nav, f.image, "y_m")) > 0.001;
  }
  EXPECT_GT(differ, 10) << "the filter's trajectory is the navigation's";
}

TEST(MissionTrajectory, AnUnwritableTrajectoryOutIsRefusedBeforeTheMapIsMade) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string log;
  EXPECT_EQ(
      Seamap(Survey().BuildArgs() + " --trajectory-out " + (dir / "no" / "such" / "t.csv").string() + " --out " + map,
             &log),
      2)
      << log;
  EXPECT_NE(log.find("--trajectory-out"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(map));
}

// A trajectory without absolute fixes (as visual odometry leaves it: the right shape, turned and shifted)
// in a mission, put on the Earth by the towed buoy: `georef --map` takes the mission's trajectory.
TEST(MissionTrajectory, GeorefPutsTheMissionsTrajectoryOnTheEarthWithTheBuoy) {
  testing::TempDir dir;
  const std::string sim = (dir / "buoy").string(), map = (dir / "vo.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap("simulate-buoy --out " + sim + " --cloud-points 100 --lines 2 --line-length 60 --seed 3", &log), 0)
      << log;
  {
    const LatLon origin{51.0563, 13.6190};
    const LocalFrame frame(origin);
    MBTilesStore store(map, MBTilesStore::Mode::kCreate);
    std::ifstream truth(sim + "/truth.csv");
    std::string line;
    std::getline(truth, line);
    const double turn = 15 * M_PI / 180;
    int id = 0;
    while (std::getline(truth, line)) {
      double t, lat, lon, x, y, depth, heading;
      ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &t, &lat, &lon, &x, &y, &depth, &heading), 7);
      const LocalXY xy = frame.FromLatLon({lat, lon});
      FrameRecord f;
      f.id = id++;
      f.image = "f" + std::to_string(f.id) + ".png";
      f.time_s = t;
      // Turned 15 degrees (counter-clockwise) about the origin and 40 m off to the east.
      f.position = frame.ToLatLon({std::cos(turn) * xy.east - std::sin(turn) * xy.north + 40,
                                   std::sin(turn) * xy.east + std::cos(turn) * xy.north});
      f.depth_m = depth, f.altitude_m = 7.5, f.heading_deg = std::fmod(heading - 15 + 360, 360);
      f.status = "used";
      store.Records().PutFrame(f);
    }
    MissionMetadata m;
    m.origin = origin;
    m.trajectory = nlohmann::json{{"mode", "vo"}};
    WriteMissionMetadata(&store, m);
    store.Flush();
  }
  const std::string common = " --buoy " + sim + "/buoy.csv --tether-length 30 --depth-csv " + sim + "/depth.csv";
  ASSERT_EQ(Seamap("georef --map " + map + common + " --quiet --out " + (dir / "mission_nav.csv").string(), &log), 0)
      << log;
  ASSERT_EQ(Seamap("georef --keyframes " + sim + "/keyframes.txt" + common + " --quiet --out " +
                       (dir / "slam_nav.csv").string(),
                   &log),
            0)
      << log;
  const auto rmse = [&](const std::string& nav) {
    const std::string json = (dir / (nav + ".json")).string();
    EXPECT_EQ(Seamap("georef-eval --nav " + (dir / nav).string() + " --truth " + sim + " --json " + json, &log), 0)
        << log;
    return nlohmann::json::parse(std::ifstream(json))["rmse_m"].get<double>();
  };
  const double mission = rmse("mission_nav.csv"), slam = rmse("slam_nav.csv");
  std::printf("georef RMSE: the mission's trajectory %.3f m, the SLAM keyframes %.3f m\n", mission, slam);
  EXPECT_LT(mission, 0.5);  // 40 m and 15 degrees off before
  EXPECT_LT(mission, 1.5 * slam);
  // One trajectory at a time.
  EXPECT_EQ(Seamap("georef --map " + map + " --keyframes " + sim + "/keyframes.txt" + common + " --out " +
                       (dir / "x.csv").string(),
                   &log),
            2)
      << log;
  EXPECT_NE(log.find("--map"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
