// A true orthophoto on the height model from the photos (build --terrain):
// the texture within a base pixel of its true ground position over 0.3 m rms
// relief, also at the swath's edges, where the model has holes (the points do
// not surround its cells there) that used to be painted on each frame's plane.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::SharedSurvey;

// The same survey as true_orthophoto_test.cc (the fixture simulates it once per name).
const testing::SimulatedSurvey& ReliefSurvey() {
  return SharedSurvey("relief_ortho",
                      "--relief 0.3 --altitude-min 2 --altitude-max 2 --line-spacing 0.9 --line-length 4 "
                      "--frames 70 --width 348 --height 260 --pixel-pitch-um 25.8 --image-format jpg --seed 3 --quiet");
}

nlohmann::json MapEval(const std::string& map, const std::string& survey_dir) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(testing::Seamap("map-eval " + map + " " + survey_dir + " --json " + json, &log), 0) << log;
  std::printf("%s", log.c_str());
  std::ifstream in(json);
  return nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
}

TEST(OrthoTerrain, OnTheModelFromThePhotosTheTextureIsWithinABasePixelUpToTheSwathsEdges) {
  const auto& survey = ReliefSurvey();
  testing::TempDir dir;
  const std::string map = (dir / "ortho.mbtiles").string(), report = (dir / "report.json").string();
  std::string log;
  ASSERT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + map + " --terrain --report " + report, &log), 0) << log;
  EXPECT_NE(log.find("painted on cells of"), std::string::npos) << log;
  const nlohmann::json e = MapEval(map, survey.dir);
  ASSERT_TRUE(e.is_object());
  EXPECT_GT(e.at("measured_blocks").get<int>(), 50);
  // Before: median 0.23, p90 0.94, max 32 px (the model's holes at the swath's
  // edges painted on each frame's plane, the bumps between 0.165 m cells cut
  // flat). Now: 0.16 / 0.60 / 1.6 px.
  EXPECT_LT(e.at("median_px").get<double>(), 0.2);
  EXPECT_LT(e.at("p90_px").get<double>(), 0.8);
  EXPECT_LT(e.at("max_px").get<double>(), 4.0);
  // The model keeps its holes (the DEM, /api/terrain); the painting does not fall back to the plane.
  const auto figures = nlohmann::json::parse(std::ifstream(report));
  const nlohmann::json& t = figures.at("terrain");
  EXPECT_GT(t.at("hole_share").get<double>(), 0.05) << t.dump();
  EXPECT_LT(t.at("painted_hole_share").get<double>(), 0.01) << t.dump();
  EXPECT_LT(t.at("painted_cell_m").get<double>(), t.at("cell_m").get<double>()) << t.dump();
}

}  // namespace
}  // namespace seamap
