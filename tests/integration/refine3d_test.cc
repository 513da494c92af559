// `seamap trajectory --mode refine` on a small drifting survey over a rugged
// seabed (0.15 m rms relief): the default method (auto) sees the relief in
// the navigation's depth + altitude and runs the bundle adjustment, which
// removes the seams that the planar registration leaves there and writes the
// seabed points it triangulated; on a flat seabed auto keeps the planar graph.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("drifting_relief",
                               "--frames 160 --line-length 6 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 "
                               "--heading-noise 0.5 --image-format jpg --seed 4 --relief 0.15 --quiet");
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

TEST(Refine3d, TheBundleAdjustmentRemovesTheSeamsOverRelief) {
  testing::TempDir dir;
  const auto& s = Survey();
  const std::string out = (dir / "refined.csv").string(), report = (dir / "report.json").string(),
                    points = (dir / "points.csv").string();
  std::string log;
  ASSERT_EQ(Seamap("trajectory --mode refine --out " + out + " --report " + report + " --points " + points +
                       " --images " + s.photo + " --nav " + s.nav + " --camera " + s.camera + " --origin " + s.origin +
                       " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --quiet",
                   &log),
            0)
      << log;
  const auto refined = Evaluate(out), raw = Evaluate(s.nav);
  std::printf("refine (bundle) over 0.15 m relief: cross-pass p90 %.1f mm (navigation %.1f mm), ATE %.4f m (%.4f m)\n",
              refined["cross_p90_mm"].get<double>(), raw["cross_p90_mm"].get<double>(), refined["ate_m"].get<double>(),
              raw["ate_m"].get<double>());
  EXPECT_GT(raw["cross_p90_mm"].get<double>(), 50);
  // Measured 5.1 mm and 5.5 mm (issue 29: p90 <= 10 mm, ATE <= 20 mm on ~800 frames). Before the
  // bundle estimated the navigation's drift its first frames carried the map off: ATE 21.7 mm.
  EXPECT_LT(refined["cross_p90_mm"].get<double>(), 10);
  EXPECT_LT(refined["ate_m"].get<double>(), 0.012);
  EXPECT_LT(refined["ate_m"].get<double>(), raw["ate_m"].get<double>() / 4);
  const auto r = nlohmann::json::parse(std::ifstream(report));
  EXPECT_EQ(r["method"], "bundle");
  EXPECT_GT(r["navigated_relief_m"].get<double>(), 0.02);  // 0.15 m rms, as the DVL's beams average it
  EXPECT_LT(r["bundle"]["reprojection_after_px"].get<double>(), 1.0);

  // The seabed points: a header and one row per point, heights near the seabed's (35 m down, +-0.5 m).
  std::ifstream in(points);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "x_m,y_m,up_m,sigma_up_m,views");
  int rows = 0;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    double x, y, up, sigma;
    char comma;
    fields >> x >> comma >> y >> comma >> up >> comma >> sigma;
    EXPECT_NEAR(up, -35, 0.6) << line;
    EXPECT_GT(sigma, 0) << line;
    ++rows;
  }
  EXPECT_GT(rows, 500);
}

TEST(Refine3d, OnAFlatSeabedAutoKeepsThePlanarGraph) {
  testing::TempDir dir;
  const auto& s = testing::DriftingSurvey();
  const std::string out = (dir / "refined.csv").string(), report = (dir / "report.json").string();
  std::string log;
  ASSERT_EQ(Seamap("trajectory --mode refine --out " + out + " --report " + report + " --images " + s.photo +
                       " --nav " + s.nav + " --camera " + s.camera + " --origin " + s.origin +
                       " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --refine-method auto --quiet",
                   &log),
            0)
      << log;
  const auto r = nlohmann::json::parse(std::ifstream(report));
  EXPECT_EQ(r["method"], "planar");
  EXPECT_LT(r["navigated_relief_m"].get<double>(), 0.005);
}

TEST(Refine3d, ABadMethodIsAnErrorNamingTheOption) {
  std::string log;
  const auto& s = Survey();
  EXPECT_EQ(Seamap("trajectory --mode refine --refine-method spline --out /dev/null --images " + s.photo + " --nav " +
                       s.nav + " --camera " + s.camera + " --origin " + s.origin + " --quiet",
                   &log),
            2)
      << log;
  EXPECT_NE(log.find("--refine-method"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
