// `seamap trajectory --mode vo` where seed 003's plane assumption breaks: a
// degraded colour survey (haze, colour cast, vignetting, noise) with the
// enhancement chain in front of the features (--feature-enhance), and bad
// values of that option.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;

// 120 frames over two 6 m lines, pitch and roll +-3 degrees, lamp-lit hazy colour frames.
const testing::SimulatedSurvey& Degraded() {
  return SharedSurvey("vo_degraded",
                      "--frames 120 --line-length 6 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 "
                      "--heading-noise 0.5 --pitch-amp 3 --roll-amp 3 --degrade --color --haze 0.7 "
                      "--image-format jpg --seed 7 --quiet");
}

std::string Common(const testing::SimulatedSurvey& s) {
  return " --images " + s.photo + " --nav " + s.nav + " --camera " + s.camera + " --origin " + s.origin +
         " --nav-noise 0.005 --nav-drift 0.5 --heading-noise 0.5 --threads 2 --quiet";
}

nlohmann::json Evaluate(const testing::SimulatedSurvey& s, const std::string& estimate) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(
      Seamap("trajectory-eval " + estimate + " " + s.dir + "/nav_truth.csv --origin " + s.origin + " --json " + json,
             &log),
      0)
      << log;
  return nlohmann::json::parse(std::ifstream(json));
}

TEST(VoRelief, AutoEnhancementIsMeasuredOnTheFirstFramesAndKeptOnlyWhereItHelps) {
  const auto& s = Degraded();
  testing::TempDir dir;
  const std::string out = (dir / "vo.csv").string(), report = (dir / "vo.json").string();
  std::string log;
  ASSERT_EQ(
      Seamap("trajectory --mode vo --feature-enhance auto --out " + out + " --report " + report + Common(s), &log), 0)
      << log;
  const auto r = nlohmann::json::parse(std::ifstream(report));
  ASSERT_TRUE(r.contains("feature_enhance")) << r.dump(2);
  const auto& e = r["feature_enhance"];
  ASSERT_GE(e["trials"].size(), 2u);
  EXPECT_EQ(e["trials"][0]["chain"], "none");
  // The chosen chain is the trial with the most inliers, and it beats none
  // by the margin (on these hazy frames one does).
  double none = e["trials"][0]["inliers_per_pair"].get<double>(), best = 0;
  std::string best_chain;
  for (const auto& t : e["trials"])
    if (t["inliers_per_pair"].get<double>() > best) {
      best = t["inliers_per_pair"].get<double>();
      best_chain = t["chain"].get<std::string>();
    }
  EXPECT_GT(best, 1.1 * none);
  EXPECT_EQ(e["chain"], best_chain);
  const auto vo = Evaluate(s, out);
  std::printf("vo, %s: drift %.3f %%, ATE %.4f m\n", best_chain.c_str(), vo["drift_percent"].get<double>(),
              vo["ate_m"].get<double>());
  EXPECT_LT(vo["drift_percent"].get<double>(), 1.5);
  EXPECT_EQ(r["failed_pairs"].get<int>(), 0);
}

TEST(VoRelief, BadFeatureEnhanceStopsWithExit2NamingTheOption) {
  const auto& s = Degraded();
  testing::TempDir dir;
  std::string log;
  EXPECT_EQ(
      Seamap("trajectory --mode vo --feature-enhance sharpen --out " + (dir / "t.csv").string() + Common(s), &log), 2);
  EXPECT_NE(log.find("sharpen"), std::string::npos) << log;
  EXPECT_EQ(Seamap("trajectory --mode vo --feature-enhance '' --out " + (dir / "t.csv").string() + Common(s), &log), 2);
  EXPECT_NE(log.find("--feature-enhance"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
