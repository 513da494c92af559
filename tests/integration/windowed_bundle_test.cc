// `seamap trajectory --mode refine --bundle-window N` on the small drifting
// survey over 0.15 m of relief (refine3d_test's): the bundle solved in
// windows of 60 frames (three windows over three lanes, each holding the
// frames before it and the earlier lane's cross-pass partners fixed, and
// going on from the navigation's drift the windows before solved) keeps the
// cross-pass and absolute accuracy of the global bundle, and the windows
// agree at their seams.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;

// The same name and options as refine3d_test.cc: one simulation for both.
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

TEST(WindowedBundle, ASurveyLongerThanOneWindowKeepsItsCrossPassAccuracy) {
  testing::TempDir dir;
  const auto& s = Survey();
  const std::string out = (dir / "refined.csv").string(), report = (dir / "report.json").string();
  std::string log;
  ASSERT_EQ(Seamap("trajectory --mode refine --bundle-window 60 --out " + out + " --report " + report + " --images " +
                       s.photo + " --nav " + s.nav + " --camera " + s.camera + " --origin " + s.origin +
                       " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --quiet",
                   &log),
            0)
      << log;
  const auto refined = Evaluate(out), raw = Evaluate(s.nav);
  const auto r = nlohmann::json::parse(std::ifstream(report));
  const auto& bundle = r["bundle"];
  std::printf(
      "refine (bundle, windows of 60 frames): cross-pass p90 %.1f mm (navigation %.1f mm), ATE %.4f m, %d windows, "
      "seam jump max %.2f mm median %.2f mm\n",
      refined["cross_p90_mm"].get<double>(), raw["cross_p90_mm"].get<double>(), refined["ate_m"].get<double>(),
      bundle["windows"].get<int>(), bundle["seam_jump_max_mm"].get<double>(),
      bundle["seam_jump_median_mm"].get<double>());
  EXPECT_EQ(r["method"], "bundle");
  EXPECT_EQ(bundle["windows"].get<int>(), 3);  // 60 + 60 + 40 frames kept
  // The global bundle: p90 5.1 mm, ATE 5.5 mm (refine3d_test.cc). Windows
  // without the drift's knots (each on absolute priors growing from the
  // survey's start) gave ATE 22.3 mm.
  EXPECT_LT(refined["cross_p90_mm"].get<double>(), 10);
  EXPECT_LT(refined["ate_m"].get<double>(), 0.012);
  EXPECT_LT(refined["ate_m"].get<double>(), raw["ate_m"].get<double>() / 4);
  EXPECT_LT(bundle["seam_jump_max_mm"].get<double>(), 2);
  EXPECT_GT(bundle["seam_jump_max_mm"].get<double>(), 0);  // the windows met: the overlap was solved twice
  EXPECT_LT(bundle["reprojection_after_px"].get<double>(), 1.0);
}

TEST(WindowedBundle, ABadWindowIsAnErrorNamingTheOption) {
  std::string log;
  const auto& s = Survey();
  EXPECT_EQ(Seamap("trajectory --mode refine --bundle-window 5 --out /dev/null --images " + s.photo + " --nav " +
                       s.nav + " --camera " + s.camera + " --origin " + s.origin + " --quiet",
                   &log),
            2)
      << log;
  EXPECT_NE(log.find("--bundle-window"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
