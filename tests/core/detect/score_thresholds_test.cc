// Issue 32: a threshold per class (seamap.class_min_scores), so a fine-tune's
// new class keeps its own validated operating point and the old classes keep
// theirs; models without it keep one threshold for all.
#include "core/detect/score_thresholds.h"

#include <gtest/gtest.h>

#include "core/detect/detection_run.h"
#include "core/detect/yolo_model.h"
#include "core/util/error.h"
#include "tests/testing/onnx_builder.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const std::vector<std::string> kNames = {"tyre", "crate"};

TEST(ClassMinScores, AnObjectOrAListInClassOrder) {
  EXPECT_EQ(ParseClassMinScores(R"({"crate": 0.7})", kNames, 0.6f, "m.onnx"), (std::vector<float>{0.6f, 0.7f}));
  EXPECT_EQ(ParseClassMinScores("[0.5, 0.75]", kNames, 0.6f, "m.onnx"), (std::vector<float>{0.5f, 0.75f}));
  for (const std::string bad : {"0.5", "[0.5]", R"({"drum": 0.5})", R"({"tyre": "high"})", R"({"tyre": 1.5})",
                                R"({"tyre": 0})", "[0.5, 0.0001]", "{"}) {
    try {
      ParseClassMinScores(bad, kNames, 0.6f, "m.onnx");
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "seamap.class_min_scores");
      EXPECT_NE(std::string(e.what()).find("m.onnx"), std::string::npos) << e.what();
    }
  }
}

TEST(ClassMinScores, ThresholdsFallBackToTheSingleOne) {
  ScoreThresholds one;
  one.all = 0.6f;
  EXPECT_FLOAT_EQ(one.For(0), 0.6f);
  EXPECT_FLOAT_EQ(one.Lowest(), 0.6f);
  const ScoreThresholds two{0.6f, {0.7f, 0.45f}};
  EXPECT_FLOAT_EQ(two.For(0), 0.7f);
  EXPECT_FLOAT_EQ(two.For(1), 0.45f);
  EXPECT_FLOAT_EQ(two.For(5), 0.6f);  // a class id past the table
  EXPECT_FLOAT_EQ(two.Lowest(), 0.45f);
}

// A planted model: a tyre scoring 0.55 and a crate scoring 0.55, far apart.
std::string PlantedModel(const testing::TempDir& dir, const std::map<std::string, std::string>& extra) {
  std::map<std::string, std::string> meta = {{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", "0.5"}};
  meta.insert(extra.begin(), extra.end());
  const auto spec = testing::PlantedYoloModel(
      {1, 6, 2}, testing::V8Values({{16, 16, 8, 8, 0.55f, 0.1f}, {48, 48, 8, 8, 0.1f, 0.55f}}), meta);
  return testing::WriteFile(dir / "m.onnx", testing::OnnxModelBytes(spec)).string();
}

std::vector<int> ClassesFound(const std::shared_ptr<const YoloModelInfo>& model, const DetectSettings& base) {
  DetectSettings s = base;
  s.model = model;
  s.zooms = {20};
  WindowSearcher searcher(s);
  const cv::Mat opaque(256, 256, CV_8UC4, cv::Scalar(90, 90, 90, 255));
  searcher.Search({20, 4, 8}, [&](const TileId&) -> std::optional<cv::Mat> { return opaque; });
  std::vector<int> classes;
  for (const RawDetection& r : searcher.Raw()) classes.push_back(r.class_id);
  std::sort(classes.begin(), classes.end());
  return classes;
}

TEST(ClassMinScores, EachClassIsCutAtItsOwnThreshold) {
  testing::TempDir dir;
  // Without per-class scores: one threshold (0.5) keeps both.
  const auto plain = YoloModel::Inspect(PlantedModel(dir, {}), "");
  EXPECT_TRUE(plain->class_min_scores.empty());
  DetectSettings settings;
  settings.min_score = plain->min_score;
  settings.class_min_scores = plain->class_min_scores;
  EXPECT_EQ(ClassesFound(plain, settings), (std::vector<int>{0, 1}));

  // The tyre validated at 0.6: its 0.55 box goes, the crate (0.5 by default) stays.
  const auto per_class = YoloModel::Inspect(PlantedModel(dir, {{"seamap.class_min_scores", R"({"tyre": 0.6})"}}), "");
  EXPECT_EQ(per_class->class_min_scores, (std::vector<float>{0.6f, 0.5f}));
  settings.min_score = per_class->min_score;
  settings.class_min_scores = per_class->class_min_scores;
  EXPECT_EQ(ClassesFound(per_class, settings), (std::vector<int>{1}));
  // A class threshold below the single one lets its boxes through.
  settings.class_min_scores = {0.4f, 0.6f};
  settings.min_score = 0.7f;
  EXPECT_EQ(ClassesFound(per_class, settings), (std::vector<int>{0}));
}

TEST(ClassMinScores, MalformedMetadataIsRefusedAtLoad) {
  testing::TempDir dir;
  try {
    YoloModel::Inspect(PlantedModel(dir, {{"seamap.class_min_scores", R"({"drum": 0.6})"}}), "");
    ADD_FAILURE() << "an unknown class accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "seamap.class_min_scores");
    EXPECT_NE(std::string(e.what()).find("drum"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
