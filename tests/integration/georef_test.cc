// `seamap simulate-buoy`, `seamap georef` and `seamap georef-eval` end to
// end: the georeferenced keyframes and cloud against the simulated truth, and
// the exit codes and messages for bad input and degenerate surveys.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/georef/point_cloud_ply.h"
#include "core/nav/csv_table.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

// After Eigen: httplib brings resolv.h, whose _res macro breaks Eigen's headers.
#include <httplib.h>

namespace seamap {
namespace {

using testing::Seamap;
using testing::TempDir;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

nlohmann::json ReadJson(const std::string& path) {
  return nlohmann::json::parse(std::ifstream(path));
}

class GeorefCli : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  void Simulate(const std::string& extra) {
    std::string log;
    ASSERT_EQ(Seamap("simulate-buoy --out " + Path("survey") + " --force --cloud-points 500 " + extra, &log), 0) << log;
  }
  // georef on the simulated survey; the exit code, output in *log.
  int Georef(const std::string& extra, std::string* log) {
    const std::string s = Path("survey") + "/";
    return Seamap("georef --keyframes " + s + "keyframes.txt --buoy " + s + "buoy.csv --tether-length 30 " +
                      "--depth-csv " + s + "depth.csv --out " + Path("nav.csv") + " --report " + Path("report.json") +
                      " " + extra,
                  log);
  }
  TempDir dir_;
};

TEST_F(GeorefCli, NoisySurveyGeoreferencedWithinItsBound) {
  Simulate("--gps-sigma 1.5 --seed 5");
  std::string log;
  ASSERT_EQ(Georef("--points " + Path("survey/cloud.ply") + " --points-out " + Path("cloud_georef.ply"), &log), 0)
      << log;
  const auto report = ReadJson(Path("report.json"));
  EXPECT_FALSE(report["degenerate"].get<bool>());
  EXPECT_EQ(report["method"], "tether");
  EXPECT_GT(report["good_keyframes"].get<int>(), 300);
  EXPECT_NEAR(report["gps_sigma_m"].get<double>(), 1.5, 0.2);
  EXPECT_EQ(report["utm_zone"], "33N");
  for (const char* key : {"scale", "rotation", "translation", "rmse_m", "n_eff", "predicted_rmse_m", "gps_bound_rmse_m",
                          "along_track_bias_m", "eigen_ratio", "rejected", "submaps"})
    EXPECT_TRUE(report.contains(key)) << key;

  // nav.csv: the header exactly, one row per keyframe.
  std::ifstream nav(Path("nav.csv"));
  std::string header;
  std::getline(nav, header);
  EXPECT_EQ(header, "time_s,lat,lon,depth_m,heading_deg,good,sigma_m");

  ASSERT_EQ(Seamap("georef-eval --nav " + Path("nav.csv") + " --truth " + Path("survey") + " --report " +
                       Path("report.json") + " --points " + Path("cloud_georef.ply") + " --json " + Path("eval.json"),
                   &log),
            0)
      << log;
  const auto eval = ReadJson(Path("eval.json"));
  EXPECT_LT(eval["rmse_m"].get<double>(), 0.5) << log;
  EXPECT_LT(eval["rmse_m"].get<double>(), 2 * report["predicted_rmse_m"].get<double>()) << log;
  EXPECT_GT(eval["rmse_m"].get<double>(), 0.33 * report["predicted_rmse_m"].get<double>()) << log;
  EXPECT_LT(eval["heading_rms_deg"].get<double>(), 1.0) << log;
  EXPECT_LT(std::fabs(eval["submaps"][0]["scale_error_pct"].get<double>()), 1.0) << log;
  EXPECT_LT(eval["cloud"]["rmse_m"].get<double>(), 0.6) << log;
  EXPECT_LT(eval["cloud"]["vertical_rmse_m"].get<double>(), 0.2) << log;

  const PointCloud cloud = ReadPly(Path("cloud_georef.ply"));
  EXPECT_EQ(cloud.size(), 500u);
  EXPECT_EQ(cloud.vertex_properties[0].type, "double");
  EXPECT_GE(cloud.Index("intensity"), 0);  // other properties kept
  EXPECT_TRUE(Contains(cloud.comments.back(), "UTM zone 33N (EPSG:32633)"));
}

TEST_F(GeorefCli, TriangleBaselineIsWorse) {
  Simulate("--gps-sigma 1.5 --seed 6");
  std::string log;
  ASSERT_EQ(Georef("", &log), 0) << log;
  ASSERT_EQ(
      Seamap("georef-eval --nav " + Path("nav.csv") + " --truth " + Path("survey") + " --json " + Path("u.json"), &log),
      0);
  ASSERT_EQ(Georef("--method triangle", &log), 0) << log;
  EXPECT_EQ(ReadJson(Path("report.json"))["triangle"]["keyframes"].size(), 3u);
  ASSERT_EQ(
      Seamap("georef-eval --nav " + Path("nav.csv") + " --truth " + Path("survey") + " --json " + Path("t.json"), &log),
      0);
  EXPECT_LT(2 * ReadJson(Path("u.json"))["rmse_m"].get<double>(), ReadJson(Path("t.json"))["rmse_m"].get<double>());
}

TEST_F(GeorefCli, AStraightLineIsRefusedWithExitTwoAndTheReason) {
  Simulate("--pattern line --lines 3 --gps-sigma 0.5");
  std::string log;
  EXPECT_EQ(Georef("", &log), 2);
  EXPECT_TRUE(Contains(log, "keyframes.txt: cannot georeference: straight line")) << log;
  EXPECT_FALSE(std::ifstream(Path("nav.csv")).good());  // no nav.csv
  const auto report = ReadJson(Path("report.json"));    // but the report says why
  EXPECT_TRUE(report["degenerate"].get<bool>());
  EXPECT_TRUE(Contains(report["reason"].get<std::string>(), "straight line"));
}

TEST_F(GeorefCli, BadInputNamesFileLineOrOption) {
  Simulate("--lines 2 --cloud-points 0");
  std::string log;
  {
    std::ofstream bad(Path("survey/keyframes.txt"), std::ios::app);
    bad << "1700009999 1 2 3 0 0 1\n";  // 7 numbers
  }
  EXPECT_EQ(Georef("", &log), 2);
  EXPECT_TRUE(Contains(log, "keyframes.txt:")) << log;
  EXPECT_TRUE(Contains(log, "expected 8 numbers")) << log;

  const std::string s = Path("survey") + "/";
  EXPECT_EQ(Seamap("georef --keyframes " + s + "keyframes.txt --buoy " + s +
                       "buoy.csv --tether-length 30 --depth 31 "
                       "--out " +
                       Path("n.csv"),
                   &log),
            2);
  EXPECT_TRUE(Contains(log, "--depth")) << log;
  EXPECT_EQ(Seamap("georef --keyframes " + s + "keyframes.txt --buoy " + s +
                       "buoy.csv --tether-length -1 --depth 3 "
                       "--out " +
                       Path("n.csv"),
                   &log),
            2);
  EXPECT_TRUE(Contains(log, "--tether-length")) << log;
  for (const char* option : {"--clock-sigma -1", "--sag-sigma 0.9", "--clock-sigma nan"}) {
    EXPECT_EQ(Seamap("georef --keyframes " + s + "keyframes.txt --buoy " + s +
                         "buoy.csv --tether-length 30 --depth 3 --out " + Path("n.csv") + " " + option,
                     &log),
              2)
        << option;
    EXPECT_TRUE(Contains(log, std::string(option).substr(0, std::string(option).find(' ')))) << log;
  }
}

TEST_F(GeorefCli, ClocksThatDoNotOverlapAreNamed) {
  Simulate("--lines 2 --clock-offset 100000 --cloud-points 0");
  std::string log;
  EXPECT_EQ(Georef("", &log), 2);
  EXPECT_TRUE(Contains(log, "no keyframe falls within the buoy's time span")) << log;
}

// nav.csv with an altitude (a sounder's log, or the cloud's seabed) is what
// seamap build reads: photos timed at keyframes land at the georeferenced
// positions, and the mission's track is the georeferenced one.
TEST_F(GeorefCli, TheGeoreferencedTrajectoryFeedsSeamapBuild) {
  Simulate("--gps-sigma 0.5 --seed 7");
  std::string log;
  ASSERT_EQ(Georef("--altitude-csv " + Path("survey/altitude.csv"), &log), 0) << log;
  const CsvTable nav = ParseCsv(ReadTextLines(Path("nav.csv")));
  ASSERT_EQ(nav.header, (std::vector<std::string>{"time_s", "lat", "lon", "depth_m", "heading_deg", "good", "sigma_m",
                                                  "altitude_m"}));
  ASSERT_GT(nav.rows.size(), 300u);
  EXPECT_NEAR(std::stod(nav.rows[100].fields[7]), 7.5, 0.6);  // seabed 20 +- 0.5 m, vehicle at 12.5 m

  // Another survey's photos, timed at keyframes 200..239 (their content does not matter here).
  const auto& photos = testing::DriftingSurvey();
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(photos.photo))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 40u);
  std::ofstream times(Path("times.csv"));
  times << "image,time_s\n";
  for (int k = 0; k < 40; ++k) times << names[k] << "," << nav.rows[200 + k].fields[0] << "\n";
  times.close();
  ASSERT_EQ(Seamap("build --images " + photos.photo + " --nav " + Path("nav.csv") + " --image-times " +
                       Path("times.csv") + " --camera " + photos.camera + " --out " + Path("map.mbtiles") + " --quiet",
                   &log),
            0)
      << log;
  const std::vector<TrackPoint> track = MBTilesStore(Path("map.mbtiles"), MBTilesStore::Mode::kReadOnly).Track();
  ASSERT_EQ(track.size(), 40u) << log;
  for (int k = 0; k < 40; ++k) {
    const auto& row = nav.rows[200 + k].fields;
    EXPECT_NEAR(track[k].position.lat, std::stod(row[1]), 1e-8) << k;
    EXPECT_NEAR(track[k].position.lon, std::stod(row[2]), 1e-8) << k;
    EXPECT_NEAR(track[k].altitude_m, std::stod(row[7]), 1e-3) << k;
  }

  // Served with the buoy's fixes and georef's keyframes: the vehicle's track,
  // the buoy's beside it, the keyframes with the ones used in the fit.
  testing::ChildProcess serve({testing::SeamapBinary(), "serve", Path("map.mbtiles"), "--host", "127.0.0.1", "--port",
                               "0", "--buoy", Path("survey/buoy.csv"), "--georef-nav", Path("nav.csv")});
  const auto line = serve.WaitForLine("serving http://", std::chrono::seconds(30));
  ASSERT_TRUE(line) << serve.output();
  httplib::Client api("127.0.0.1", testing::PortFromServingLine(*line));
  auto res = api.Get("/api/track?source=buoy");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  const auto buoy = nlohmann::json::parse(res->body);
  const CsvTable fixes = ParseCsv(ReadTextLines(Path("survey/buoy.csv")));
  EXPECT_EQ(buoy["properties"]["source"], "buoy");
  ASSERT_EQ(buoy["geometry"]["coordinates"].size(), fixes.rows.size());
  EXPECT_NEAR(buoy["geometry"]["coordinates"][10][1].get<double>(), std::stod(fixes.rows[10].fields[1]), 1e-9);
  EXPECT_NEAR(buoy["geometry"]["coordinates"][10][0].get<double>(), std::stod(fixes.rows[10].fields[2]), 1e-9);
  res = api.Get("/api/track?source=buoy&since=" + std::to_string(fixes.rows.size() - 2));
  ASSERT_TRUE(res);
  EXPECT_EQ(nlohmann::json::parse(res->body)["properties"]["times"].size(), 3u);  // from the point before
  res = api.Get("/api/track");
  ASSERT_TRUE(res);
  const auto vehicle = nlohmann::json::parse(res->body);
  ASSERT_EQ(vehicle["geometry"]["coordinates"].size(), 40u);
  EXPECT_NEAR(vehicle["geometry"]["coordinates"][0][1].get<double>(), std::stod(nav.rows[200].fields[1]), 1e-8);
  res = api.Get("/api/keyframes");
  ASSERT_TRUE(res);
  const auto keyframes = nlohmann::json::parse(res->body);
  ASSERT_EQ(keyframes["features"].size(), nav.rows.size());
  size_t good = 0, served_good = 0;
  for (size_t k = 0; k < nav.rows.size(); ++k) {
    good += std::stod(nav.rows[k].fields[5]) != 0;
    served_good += keyframes["features"][k]["properties"]["good"].get<bool>();
    // Each keyframe's predicted error, as nav.csv has it.
    EXPECT_NEAR(keyframes["features"][k]["properties"]["sigma_m"].get<double>(), std::stod(nav.rows[k].fields[6]),
                1e-9);
  }
  EXPECT_EQ(served_good, good);
  EXPECT_GT(good, 0u);
  EXPECT_LT(good, nav.rows.size());  // turns: slack tether, keyframes dropped
  EXPECT_NEAR(keyframes["features"][5]["geometry"]["coordinates"][1].get<double>(), std::stod(nav.rows[5].fields[1]),
              1e-9);
  res = api.Get("/api/status");
  ASSERT_TRUE(res);
  const auto status = nlohmann::json::parse(res->body);
  EXPECT_EQ(status["buoy_fixes"], fixes.rows.size());
  EXPECT_EQ(status["keyframes"], nav.rows.size());
  // A nav.csv without the `good` column is refused before serving, naming it.
  EXPECT_EQ(Seamap("serve " + Path("map.mbtiles") + " --georef-nav " + Path("survey/buoy.csv"), &log), 2) << log;
  EXPECT_TRUE(Contains(log, "buoy.csv")) << log;
  EXPECT_TRUE(Contains(log, "good")) << log;
  res = api.Get("/api/track?source=sonar");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_TRUE(Contains(res->body, "'buoy'")) << res->body;
}

TEST_F(GeorefCli, AltitudeFromTheGeoreferencedCloud) {
  Simulate("--gps-sigma 0.5 --seed 8 --cloud-points 20000");
  std::string log;
  ASSERT_EQ(
      Georef("--altitude-from-cloud --points " + Path("survey/cloud.ply") + " --points-out " + Path("cloud_georef.ply"),
             &log),
      0)
      << log;
  const CsvTable nav = ParseCsv(ReadTextLines(Path("nav.csv")));
  const CsvTable truth = ParseCsv(ReadTextLines(Path("survey/altitude.csv")));
  ASSERT_EQ(nav.header.back(), "altitude_m");
  int with = 0;
  double sq = 0;
  for (const auto& row : nav.rows) {
    if (row.fields.size() < 8 || row.fields[7].empty()) continue;
    // altitude.csv has a sample each second from the survey's start: the nearest one.
    const double t = std::stod(row.fields[0]) - std::stod(truth.rows[0].fields[0]);
    const auto& sample = truth.rows.at(static_cast<size_t>(std::lround(t))).fields;
    sq += std::pow(std::stod(row.fields[7]) - std::stod(sample[1]), 2);
    ++with;
  }
  EXPECT_GT(with, static_cast<int>(nav.rows.size() * 9 / 10));
  EXPECT_LT(std::sqrt(sq / with), 0.25);  // the seabed undulates +- 0.5 m; 2 m patches, 0.3 s between samples

  EXPECT_EQ(Georef("--altitude-from-cloud", &log), 2);
  EXPECT_TRUE(Contains(log, "--altitude-from-cloud")) << log;
}

}  // namespace
}  // namespace seamap
