// Issue 32: a model's per-class thresholds (seamap.class_min_scores), end to
// end: `seamap detect` and `build --detect` keep each class at its own
// threshold, --min-score overrides them, malformed ones are refused.
#include <gtest/gtest.h>

#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/onnx_builder.h"

namespace seamap {
namespace {

using testing::Seamap;

const testing::SimulatedSurvey& Survey() {  // the hostile-model tests' survey, same options
  return testing::SharedSurvey("hostile_model", "--frames 40 --line-length 3 --seed 3");
}

// Every window: a tyre scoring 0.8 and a crate scoring 0.9, far apart.
std::string Model(const testing::TempDir& dir, const std::string& name, const std::string& class_min_scores) {
  std::map<std::string, std::string> meta = {{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", "0.5"}};
  if (!class_min_scores.empty()) meta["seamap.class_min_scores"] = class_min_scores;
  const auto spec = testing::PlantedYoloModel(
      {1, 6, 2}, testing::V8Values({{20, 24, 10, 8, 0.8f, 0.1f}, {44, 40, 12, 12, 0.1f, 0.9f}}), meta);
  return testing::WriteFile(dir / name, testing::OnnxModelBytes(spec)).string();
}

std::map<std::string, int> Classes(const std::string& map) {
  std::map<std::string, int> n;
  for (const Detection& d : OpenExistingMap(map, false)->Records().Detections())
    if (d.source == "recogniser") ++n[d.class_name];
  return n;
}

TEST(ClassThresholds, EachClassIsKeptAtItsOwnThreshold) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string(), model = Model(dir, "m.onnx", R"({"crate": 0.95})");
  std::string out;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + map, &out), 0) << out;
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + model, &out), 0) << out;
  auto found = Classes(map);
  EXPECT_GT(found["tyre"], 0) << out;
  EXPECT_EQ(found["crate"], 0) << out;  // 0.9 < its 0.95
  // --min-score sets one threshold for all.
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + model + " --min-score 0.5", &out), 0) << out;
  found = Classes(map);
  EXPECT_GT(found["tyre"], 0);
  EXPECT_GT(found["crate"], 0);
  // The live search during a build applies them too.
  const std::string built = (dir / "b.mbtiles").string();
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + built + " --detect --detect-model " + model, &out), 0) << out;
  found = Classes(built);
  EXPECT_GT(found["tyre"], 0) << out;
  EXPECT_EQ(found["crate"], 0) << out;
}

TEST(ClassThresholds, MalformedOnesAreRefusedNamingTheKey) {
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap(Survey().BuildArgs() + " --out " + map, &out), 0) << out;
  for (const std::string bad : {R"({"drum": 0.5})", R"({"tyre": 2})", "[0.5]", "high"}) {
    EXPECT_EQ(Seamap("detect --quiet " + map + " --model " + Model(dir, "bad.onnx", bad), &out), 2) << bad;
    EXPECT_NE(out.find("seamap.class_min_scores"), std::string::npos) << out;
    EXPECT_NE(out.find("bad.onnx"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace seamap
