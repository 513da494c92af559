// `seamap simulate-buoy`, `seamap georef` and `seamap georef-eval` end to
// end: the georeferenced keyframes and cloud against the simulated truth, and
// the exit codes and messages for bad input and degenerate surveys.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "core/georef/point_cloud_ply.h"
#include "tests/integration/survey_fixture.h"

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
  EXPECT_EQ(report["method"], "umeyama");
  EXPECT_GT(report["good_keyframes"].get<int>(), 300);
  EXPECT_NEAR(report["gps_sigma_m"].get<double>(), 1.5, 0.2);
  EXPECT_EQ(report["utm_zone"], "33N");
  for (const char* key : {"scale", "rotation", "translation", "rmse_m", "n_eff", "predicted_rmse_m",
                          "along_track_bias_m", "eigen_ratio", "rejected", "submaps"})
    EXPECT_TRUE(report.contains(key)) << key;

  // nav.csv: the header exactly, one row per keyframe.
  std::ifstream nav(Path("nav.csv"));
  std::string header;
  std::getline(nav, header);
  EXPECT_EQ(header, "time_s,lat,lon,depth_m,heading_deg,good");

  ASSERT_EQ(Seamap("georef-eval --nav " + Path("nav.csv") + " --truth " + Path("survey") + " --report " +
                       Path("report.json") + " --points " + Path("cloud_georef.ply") + " --json " + Path("eval.json"),
                   &log),
            0)
      << log;
  const auto eval = ReadJson(Path("eval.json"));
  EXPECT_LT(eval["rmse_m"].get<double>(), 0.5) << log;
  EXPECT_LT(eval["rmse_m"].get<double>(), 2 * report["predicted_rmse_m"].get<double>()) << log;
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
}

TEST_F(GeorefCli, ClocksThatDoNotOverlapAreNamed) {
  Simulate("--lines 2 --clock-offset 100000 --cloud-points 0");
  std::string log;
  EXPECT_EQ(Georef("", &log), 2);
  EXPECT_TRUE(Contains(log, "no keyframe falls within the buoy's time span")) << log;
}

}  // namespace
}  // namespace seamap
