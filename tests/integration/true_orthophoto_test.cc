// A true orthophoto (build --terrain-file): over 0.3 m rms relief at 2 m
// altitude the flat projection puts raised ground pixels off its true
// position; projected onto the true height model the map's texture must sit
// within a base pixel of the truth (map-eval against the simulator's truth
// texture, which over relief is the true orthophoto).
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::SharedSurvey;

// Small frames (a quarter of the default's pixels, same field of view) keep the ray-cast survey quick.
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

TEST(TrueOrthophoto, OnTheTrueHeightModelTheTextureIsWithinABasePixel) {
  const auto& survey = ReliefSurvey();
  testing::TempDir dir;
  const std::string flat = (dir / "flat.mbtiles").string(), ortho = (dir / "ortho.mbtiles").string();
  std::string log;
  ASSERT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + flat, &log), 0) << log;
  ASSERT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + ortho + " --terrain-file " + survey.dir +
                                "/truth/terrain.tif --report " + (dir / "report.json").string(),
                            &log),
            0)
      << log;
  EXPECT_NE(log.find("terrain file"), std::string::npos) << log;  // the build says what it painted onto
  const nlohmann::json f = MapEval(flat, survey.dir), o = MapEval(ortho, survey.dir);
  ASSERT_TRUE(f.is_object() && o.is_object());
  // The relief shows on a flat map (the measurement sees it) ...
  EXPECT_GT(f.at("p90_px").get<double>(), 2.0);
  // ... and the true orthophoto puts it back (the target: p90 <= 1 px, median <= 0.5 px).
  EXPECT_GT(o.at("measured_blocks").get<int>(), 30);
  EXPECT_LT(o.at("p90_px").get<double>(), 1.0);
  EXPECT_LT(o.at("median_px").get<double>(), 0.5);
  // The report says where the height model came from and how much of it was missing.
  std::ifstream in(dir / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
  ASSERT_TRUE(report.is_object() && report.contains("terrain"));
  EXPECT_LT(report["terrain"]["hole_share"].get<double>(), 0.01);
}

TEST(TrueOrthophoto, ABadHeightModelIsRefusedBeforeTheMapIsMade) {
  const auto& survey = ReliefSurvey();
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  const std::string not_a_dem = (dir / "dem.tif").string();
  std::ofstream(not_a_dem) << "not a raster";
  std::string log;
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + " --terrain-file " + not_a_dem, &log), 2);
  EXPECT_NE(log.find("dem.tif"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + " --terrain --terrain-file " + not_a_dem, &log), 2);
  EXPECT_NE(log.find("--terrain-file"), std::string::npos) << log;
}

TEST(TrueOrthophoto, PhotosThatShowNoSeabedAreAClearErrorAndLeaveNoMap) {
  const auto& survey = ReliefSurvey();
  testing::TempDir dir;
  // The survey's navigation over photos without any texture: nothing to triangulate.
  const std::filesystem::path photos = dir / "photo";
  std::filesystem::create_directories(photos);
  const auto camera = nlohmann::json::parse(std::ifstream(survey.camera));
  const cv::Mat blank(camera.at("height").get<int>(), camera.at("width").get<int>(), CV_8UC1, cv::Scalar(128));
  for (const auto& entry : std::filesystem::directory_iterator(survey.photo))
    ASSERT_TRUE(cv::imwrite((photos / entry.path().filename()).string(), blank));
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  EXPECT_EQ(testing::Seamap("build --images " + photos.string() + " --nav " + survey.nav + " --camera " +
                                survey.camera + " --origin " + survey.origin + " --out " + out + " --terrain --quiet",
                            &log),
            2);
  EXPECT_NE(log.find("--terrain: no seabed point could be triangulated"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out)) << "a failed estimate must not leave a map behind";
}

TEST(TrueOrthophoto, TheEstimatesKnobsReachItAndAreCheckedFirst) {
  const auto& survey = ReliefSurvey();
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string(), report = (dir / "report.json").string();
  std::string log;
  // Without --terrain there is no estimate to tune; a value out of range is named; neither leaves a map.
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + " --dem-cell 0.2", &log), 2);
  EXPECT_NE(log.find("--dem-cell: applies to the height model --terrain estimates"), std::string::npos) << log;
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + " --terrain --max-relief -1", &log), 2);
  EXPECT_NE(log.find("--max-relief: expected metres in (0, 1000]"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out));
  // A coarser cell than the automatic one (about 0.1 m here) is the model's cell.
  ASSERT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + " --terrain --dem-cell 0.25 --dem-max-sigma 0.1 " +
                                "--report " + report,
                            &log),
            0)
      << log;
  const auto figures = nlohmann::json::parse(std::ifstream(report));
  EXPECT_DOUBLE_EQ(figures.at("terrain").at("cell_m").get<double>(), 0.25) << figures.dump();
}

}  // namespace
}  // namespace seamap
