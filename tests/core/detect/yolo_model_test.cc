#include "core/detect/yolo_model.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const std::string kFixtures = std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/";

std::string ErrorOf(const std::string& model, const std::string& classes = "") {
  try {
    YoloModel::Inspect(model, classes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(YoloModel, V5FixtureRunsThroughOpenCvAndTheDecoder) {
  auto info = YoloModel::Inspect(kFixtures + "yolo_v5_fixture.onnx", "");
  EXPECT_EQ(info->layout, YoloLayout::kV5);
  EXPECT_EQ(info->input, cv::Size(64, 64));
  EXPECT_EQ(info->class_names, (std::vector<std::string>{"tyre", "crate"}));
  EXPECT_EQ(info->output_shape, (std::vector<int>{1, 3, 7}));
  EXPECT_EQ(info->name.rfind("yolo_v5_fixture.onnx#", 0), 0u);
  YoloModel model(info);
  // A 128 px image: letterbox scale 0.5, so boxes come back doubled.
  const auto boxes = model.Detect(cv::Mat(128, 128, CV_8UC3, cv::Scalar(50, 60, 70)), 0.4f);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_EQ(boxes[0].class_id, 0);
  EXPECT_NEAR(boxes[0].score, 0.855f, 1e-5);
  EXPECT_NEAR(boxes[0].x0, 2 * (44 - 6), 1e-3);
  EXPECT_EQ(boxes[1].class_id, 1);
  EXPECT_NEAR(boxes[1].score, 0.72f, 1e-5);
  EXPECT_NEAR(boxes[1].y1, 2 * (24 + 4), 1e-3);
}

TEST(YoloModel, V8FixtureIsRecognisedWithItsMetadata) {
  auto info = YoloModel::Inspect(kFixtures + "yolo_v8_fixture.onnx", "");
  EXPECT_EQ(info->layout, YoloLayout::kV8);
  EXPECT_EQ(info->class_sizes_m, (std::vector<double>{1.0, 1.2}));
  EXPECT_EQ(info->layer, "raw");
  EXPECT_FLOAT_EQ(info->min_score, 0.5f);  // seamap.min_score; without it 0.4 (the v5 fixture)
  EXPECT_FLOAT_EQ(YoloModel::Inspect(kFixtures + "yolo_v5_fixture.onnx", "")->min_score, 0.4f);
  const std::string bad = ErrorOf(kFixtures + "yolo_bad_min_score_fixture.onnx");
  EXPECT_NE(bad.find("yolo_bad_min_score_fixture.onnx"), std::string::npos) << bad;
  EXPECT_NE(bad.find("seamap.min_score"), std::string::npos) << bad;
  YoloModel model(info);
  const auto boxes = model.Detect(cv::Mat(64, 64, CV_8UC3, cv::Scalar(0)), 0.4f);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_NEAR(boxes[0].score, 0.9f, 1e-5);
  EXPECT_NEAR(boxes[1].score, 0.8f, 1e-5);
  EXPECT_NEAR(boxes[1].x0, 15, 1e-3);
}

TEST(YoloModel, BadModelsAreRefusedNamingTheFile) {
  testing::TempDir dir;
  const auto text = testing::WriteFile(dir / "model.onnx", "not a model at all\n");
  const std::string e1 = ErrorOf(text.string());
  EXPECT_NE(e1.find("model.onnx"), std::string::npos) << e1;
  EXPECT_NE(e1.find("not an ONNX model"), std::string::npos) << e1;
  const std::string e2 = ErrorOf(kFixtures + "yolo_bad_output_fixture.onnx");
  EXPECT_NE(e2.find("yolo_bad_output_fixture.onnx"), std::string::npos) << e2;
  EXPECT_NE(e2.find("[1, 10]"), std::string::npos) << e2;
  const auto three = testing::WriteFile(dir / "names.txt", "tyre\ncrate\npipe\n");
  const std::string e3 = ErrorOf(kFixtures + "yolo_v8_fixture.onnx", three.string());
  EXPECT_NE(e3.find("names.txt"), std::string::npos) << e3;
  EXPECT_NE(e3.find("3 classes"), std::string::npos) << e3;
  EXPECT_NE(ErrorOf((dir / "absent.onnx").string()).find("absent.onnx"), std::string::npos);
}

TEST(YoloModel, ClassesFileWinsOverMetadata) {
  testing::TempDir dir;
  const auto names = testing::WriteFile(dir / "names.txt", "ring\nbox\n");
  auto info = YoloModel::Inspect(kFixtures + "yolo_v8_fixture.onnx", names.string());
  EXPECT_EQ(info->class_names, (std::vector<std::string>{"ring", "box"}));
  EXPECT_NE(info->names_source.find("--classes"), std::string::npos);
}

}  // namespace
}  // namespace seamap
