// `seamap trajectory-eval` end to end on a small simulated survey whose
// navigation drifts; and trajectory.csv read as is by build and trajectory-eval.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/nav/nav_reader.h"
#include "core/trajectory/trajectory_csv.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;

const testing::SimulatedSurvey& Survey() {
  return testing::DriftingSurvey();
}

std::string Truth() {
  return Survey().dir + "/nav_truth.csv";
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Runs trajectory-eval with --json; the JSON, or a failure with the log.
nlohmann::json Evaluate(const std::string& estimate, const std::string& truth, std::string* log) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  const int rc =
      Seamap("trajectory-eval " + estimate + " " + truth + " --origin " + Survey().origin + " --json " + json, log);
  EXPECT_EQ(rc, 0) << *log;
  if (rc != 0) return nlohmann::json::object();
  return nlohmann::json::parse(std::ifstream(json));
}

TEST(TrajectoryEval, DriftingNavigationShowsSeamsBetweenPasses) {
  std::string log;
  const auto j = Evaluate(Survey().nav, Truth(), &log);
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["frames"], 160);
  EXPECT_EQ(j["paired_by"], "image");
  EXPECT_GE(j["lines"].get<int>(), 2);
  // 0.5 m/min over 32 s: at most 0.27 m, plus noise.
  EXPECT_GT(j["ate_m"].get<double>(), 0.03);
  EXPECT_LT(j["max_error_m"].get<double>(), 0.35);
  EXPECT_GT(j["end_error_m"].get<double>(), 0.2);
  EXPECT_NEAR(j["drift_percent"].get<double>(), 100 * j["max_error_m"].get<double>() / j["path_length_m"].get<double>(),
              1e-9);
  EXPECT_NEAR(j["path_length_m"].get<double>(), 15.9, 0.2);  // 159 steps of 0.1 m, shorter chords in turns
  // Neighbouring passes flown up to ~25 s apart disagree by centimetres.
  EXPECT_GT(j["cross_pairs"].get<int>(), 100);
  EXPECT_GT(j["cross_p90_mm"].get<double>(), 50);
  EXPECT_GE(j["cross_max_mm"].get<double>(), j["cross_p90_mm"].get<double>());
  EXPECT_GE(j["cross_p90_mm"].get<double>(), j["cross_median_mm"].get<double>());
  // Position noise shows in surge and sway; depth is exact in the simulated
  // navigation, so heave sees only the horizontal error tilted by pitch and roll (3, 2 degrees).
  const double u = j["velocity"]["u"]["rmse_mps"].get<double>(), v = j["velocity"]["v"]["rmse_mps"].get<double>();
  EXPECT_GT(u, 0.005);
  EXPECT_GT(v, 0.005);
  EXPECT_LT(j["velocity"]["w"]["rmse_mps"].get<double>(), 0.1 * std::hypot(u, v));
  for (const char* line :
       {"ATE (RMS)", "drift", "end-point error", "RMSE north/east", "cross-pass pairs", "160 paired"})
    EXPECT_TRUE(Contains(log, line)) << line << "\n" << log;
}

TEST(TrajectoryEval, TruthAgainstItselfIsAllZeros) {
  std::string log;
  const auto j = Evaluate(Truth(), Truth(), &log);
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["frames"], 160);
  EXPECT_GT(j["cross_pairs"].get<int>(), 100);
  for (const char* key : {"ate_m", "rmse_north_m", "rmse_east_m", "max_error_m", "drift_percent", "end_error_m",
                          "cross_median_mm", "cross_p90_mm", "cross_max_mm"})
    EXPECT_EQ(j[key].get<double>(), 0) << key;
  for (const char* axis : {"u", "v", "w"}) EXPECT_EQ(j["velocity"][axis]["rmse_mps"].get<double>(), 0) << axis;
}

TEST(TrajectoryEval, TrajectoryCsvIsReadAsIsByBuildAndTrajectoryEval) {
  NavReadOptions options;
  options.origin = LatLon{43.1, 131.9};
  const NavTable truth = ReadNavigation(Truth(), options);
  std::vector<TrajectoryRow> rows;
  for (const NavRecord& r : truth.records)
    rows.push_back({r.image, r.time_s, r.pose, rows.size() % 7 ? "" : "nav_only"});
  rows.resize(40);  // a quick build
  testing::TempDir dir;
  const std::string path = (dir / "trajectory.csv").string();
  WriteTrajectoryCsv(path, rows, LocalFrame(*options.origin));

  std::string log;
  ASSERT_EQ(Seamap("build --images " + Survey().photo + " --nav " + path + " --camera " + Survey().camera +
                       " --quiet --out " + (dir / "m.mbtiles").string(),
                   &log),
            0)
      << log;
  EXPECT_TRUE(Contains(log, "frames used 40, rejected 0")) << log;

  // lat/lon against the truth's x_m/y_m: the same poses to well under a millimetre.
  const auto j = Evaluate(path, Truth(), &log);
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["frames"], 40);
  EXPECT_LT(j["max_error_m"].get<double>(), 1e-4);
}

TEST(TrajectoryEval, BadInputStopsWithExit2NamingTheProblem) {
  std::string log;
  EXPECT_EQ(Seamap("trajectory-eval --help", &log), 0);
  EXPECT_TRUE(Contains(log, "usage: seamap trajectory-eval ESTIMATE TRUTH")) << log;

  EXPECT_EQ(Seamap("trajectory-eval /no/such/est.csv " + Truth() + " --origin 43.1,131.9", &log), 2);
  EXPECT_TRUE(Contains(log, "/no/such/est.csv")) << log;

  EXPECT_EQ(Seamap("trajectory-eval " + Survey().nav + " " + Truth() + " --origin 43.1,131.9 --bogus 1", &log), 2);
  EXPECT_TRUE(Contains(log, "--bogus")) << log;

  EXPECT_EQ(Seamap("trajectory-eval " + Survey().nav + " " + Truth(), &log), 2);  // x_m/y_m need an origin
  EXPECT_TRUE(Contains(log, "--origin")) << log;
  EXPECT_TRUE(Contains(log, Survey().nav + ":1")) << log;

  EXPECT_EQ(Seamap("trajectory-eval " + Survey().nav + " --origin 43.1,131.9", &log), 2);
  EXPECT_TRUE(Contains(log, "ESTIMATE TRUTH")) << log;

  EXPECT_EQ(Seamap("trajectory-eval " + Survey().nav + " " + Truth() + " --origin 43.1", &log), 2);
  EXPECT_TRUE(Contains(log, "--origin")) << log;

  // Other names and no times: nothing to pair.
  testing::TempDir dir;
  const std::string other =
      testing::WriteFile(dir / "other.csv", "image,x_m,y_m,altitude_m\nx1.jpg,0,0,2\nx2.jpg,1,0,2\n").string();
  EXPECT_EQ(Seamap("trajectory-eval " + other + " " + Truth() + " --origin 43.1,131.9", &log), 2);
  EXPECT_TRUE(Contains(log, other)) << log;
  EXPECT_TRUE(Contains(log, "no frame in common with " + Truth())) << log;

  EXPECT_EQ(
      Seamap("trajectory-eval " + Survey().nav + " " + Truth() + " --origin 43.1,131.9 --json /no/such/dir/e.json",
             &log),
      2);
  EXPECT_TRUE(Contains(log, "--json")) << log;
}

}  // namespace
}  // namespace seamap
