// `seamap trajectory` end to end on a small simulated survey whose navigation
// drifts (the same survey as trajectory_eval_test): refine removes the seams
// between passes, vo follows the photos and not the drift, and both write a
// trajectory.csv that build and trajectory-eval read.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;

const testing::SimulatedSurvey& Survey() {
  return testing::DriftingSurvey();
}

std::string Common(const std::string& nav) {
  const auto& s = Survey();
  return " --images " + s.photo + " --nav " + nav + " --camera " + s.camera + " --origin " + s.origin +
         " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --quiet";
}

nlohmann::json Evaluate(const std::string& estimate) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(Seamap("trajectory-eval " + estimate + " " + Survey().dir + "/nav_truth.csv --origin " + Survey().origin +
                       " --json " + json,
                   &log),
            0)
      << log;
  return nlohmann::json::parse(std::ifstream(json));
}

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Trajectory, RefineRemovesTheSeamsBetweenPasses) {
  testing::TempDir dir;
  const std::string out = (dir / "refined.csv").string(), report = (dir / "report.json").string();
  std::string log;
  ASSERT_EQ(Seamap("trajectory --mode refine --out " + out + " --report " + report + Common(Survey().nav), &log), 0)
      << log;
  const auto refined = Evaluate(out), raw = Evaluate(Survey().nav);
  std::printf("refine: cross-pass p90 %.1f mm (navigation %.1f mm), ATE %.4f m (navigation %.4f m)\n",
              refined["cross_p90_mm"].get<double>(), raw["cross_p90_mm"].get<double>(), refined["ate_m"].get<double>(),
              raw["ate_m"].get<double>());
  EXPECT_GT(raw["cross_p90_mm"].get<double>(), 50);
  EXPECT_LT(refined["cross_p90_mm"].get<double>(), 20);
  EXPECT_LE(refined["ate_m"].get<double>(), raw["ate_m"].get<double>());
  const auto r = nlohmann::json::parse(std::ifstream(report));
  EXPECT_GT(r["registered_cross_line"].get<int>(), 20);
  EXPECT_EQ(r["frames_without_features"], 0);
  EXPECT_LT(r["residual_after_mm"].get<double>(), r["residual_before_mm"].get<double>() / 10);
}

TEST(Trajectory, VisualOdometryFollowsThePhotosNotTheNavigationsPositions) {
  testing::TempDir dir;
  const std::string out = (dir / "vo.csv").string();
  std::string log;
  ASSERT_EQ(Seamap("trajectory --mode vo --out " + out + Common(Survey().nav), &log), 0) << log;
  const auto vo = Evaluate(out);
  std::printf("vo: drift %.3f %% of distance, ATE %.4f m\n", vo["drift_percent"].get<double>(),
              vo["ate_m"].get<double>());
  EXPECT_LT(vo["drift_percent"].get<double>(), 1.0);
  // After the first fix the navigation's positions are not used: moved by
  // 100 m, every later line gives the same trajectory.
  const std::string moved = (dir / "moved.csv").string();
  {
    std::ifstream in(Survey().nav);
    std::ofstream o(moved);
    std::string line;
    std::getline(in, line);
    o << line << "\n";  // header: image,time_s,x_m,y_m,...
    std::getline(in, line);
    o << line << "\n";  // the first fix
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::stringstream s(line);
      for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
      cells[2] = std::to_string(std::stod(cells[2]) + 100);
      for (size_t k = 0; k < cells.size(); ++k) o << (k ? "," : "") << cells[k];
      o << "\n";
    }
  }
  const std::string again = (dir / "vo_moved.csv").string();
  ASSERT_EQ(Seamap("trajectory --mode vo --out " + again + Common(moved), &log), 0) << log;
  EXPECT_EQ(Read(out), Read(again));
}

TEST(Trajectory, BadModesAndMissingTimesStopWithExit2) {
  std::string log;
  testing::TempDir dir;
  EXPECT_EQ(Seamap("trajectory --mode slam --out " + (dir / "t.csv").string() + Common(Survey().nav), &log), 2);
  EXPECT_NE(log.find("--mode"), std::string::npos) << log;
  // A navigation without times cannot drive the filter.
  const std::string timeless = (dir / "timeless.csv").string();
  {
    std::ifstream in(Survey().nav);
    std::ofstream o(timeless);
    std::string line;
    while (std::getline(in, line)) {
      const size_t a = line.find(','), b = line.find(',', a + 1);
      o << line.substr(0, a) << line.substr(b) << "\n";  // drop the time_s column
    }
  }
  EXPECT_EQ(Seamap("trajectory --mode vo --out " + (dir / "t.csv").string() + Common(timeless), &log), 2);
  EXPECT_NE(log.find("time_s"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
