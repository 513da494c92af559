// With exact navigation, the base-zoom mosaic must sit where the ground truth
// says: `seamap map-eval` (block-wise phase correlation between built tiles
// and the simulator's texture resampled into the same tiles).
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::SharedSurvey;

struct Offsets {
  double median_px = 0, p90_px = 0;
  int blocks = 0;
};

// map-eval's figures for a map against a survey's truth.
Offsets MapEval(const std::string& map, const std::string& survey_dir) {
  testing::TempDir dir;
  const std::string json = (dir / "eval.json").string();
  std::string log;
  EXPECT_EQ(testing::Seamap("map-eval " + map + " " + survey_dir + " --json " + json, &log), 0) << log;
  std::printf("%s", log.c_str());
  std::ifstream in(json);
  const nlohmann::json figures = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!figures.is_object()) {
    ADD_FAILURE() << "map-eval wrote no JSON: " << log;
    return {};
  }
  EXPECT_GT(figures.at("tiles").get<int>(), 4);
  EXPECT_GT(figures.at("measured_blocks").get<int>(), 30) << "too few fully covered blocks to judge";
  return {figures.at("median_px").get<double>(), figures.at("p90_px").get<double>(),
          figures.at("measured_blocks").get<int>()};
}

// Offsets (pixels) between built base-zoom blocks and the truth, for a build
// of the shared survey with `origin` as --origin.
Offsets MeasureOffsets(const std::string& origin, const std::string& extra = "") {
  auto survey = SharedSurvey("accuracy", "--frames 60 --line-length 4 --seed 11");
  survey.origin = origin;
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + extra, &log), 0) << log;
  return MapEval(out, survey.dir);  // the truth is georeferenced at 43.1, 131.9
}

TEST(Accuracy, BaseZoomMosaicMatchesGroundTruth) {
  const Offsets o = MeasureOffsets("43.1,131.9");
  RecordProperty("median_offset_px", std::to_string(o.median_px));
  RecordProperty("p90_offset_px", std::to_string(o.p90_px));
  EXPECT_LT(o.median_px, 1.0);
  EXPECT_LT(o.p90_px, 2.0);
}

TEST(Accuracy, RefiningExactNavigationDoesNotMakeTheMapWorse) {
  // The navigation is exact (to its stated millimetre): refinement from the
  // photos must leave the mosaic within a base pixel of the truth.
  const Offsets o = MeasureOffsets("43.1,131.9", " --refine-nav --nav-noise 0.001 --nav-drift 0 --quiet");
  EXPECT_LT(o.median_px, 1.0);
  EXPECT_LT(o.p90_px, 2.0);
}

TEST(Accuracy, TheMeasurementSeesAShiftOfTwoPixels) {
  // 1e-7 degrees of longitude at 43.1 N is 8.1 mm: 2.4 pixels at zoom 25.
  const Offsets o = MeasureOffsets("43.1,131.9000001");
  EXPECT_NEAR(o.median_px, 2.4, 0.4);
}

}  // namespace
}  // namespace seamap
