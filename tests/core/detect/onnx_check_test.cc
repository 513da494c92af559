// Issue 33, row 2: models OpenCV would crash on are refused before it reads
// them, naming the model and the tensor or node; rows 10/14: class names and
// the classes file.
#include "core/detect/onnx_check.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/detect/onnx_meta.h"
#include "core/detect/yolo_model.h"
#include "core/util/error.h"
#include "tests/testing/onnx_builder.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::OnnxModelBytes;
using testing::OnnxModelSpec;
using testing::PlantedYoloModel;
using testing::V8Values;

const std::map<std::string, std::string> kNames = {{"names", R"(["tyre", "crate"])"}};

OnnxModelSpec TwoBoxModel() {
  return PlantedYoloModel({1, 6, 2}, V8Values({{20, 24, 10, 8, 0.1f, 0.8f}, {44, 40, 12, 12, 0.9f, 0.2f}}), kNames);
}

// The message of the InputError that checking `bytes` throws ("no error" when none).
std::string CheckError(const std::string& bytes) {
  try {
    ParseOnnxInfo(bytes, "hostile.onnx");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(OnnxCheck, HandBuiltModelPassesAndRunsInOpenCv) {
  testing::TempDir dir;
  const auto path = testing::WriteFile(dir / "planted.onnx", OnnxModelBytes(TwoBoxModel()));
  EXPECT_EQ(CheckError(OnnxModelBytes(TwoBoxModel())), "no error");
  const auto info = YoloModel::Inspect(path.string(), "");
  EXPECT_EQ(info->layout, YoloLayout::kV8);
  EXPECT_EQ(info->output_shape, (std::vector<int>{1, 6, 2}));
  YoloModel model(info);
  const auto boxes = model.Detect(cv::Mat(64, 64, CV_8UC3, cv::Scalar::all(90)), 0.5f);
  ASSERT_EQ(boxes.size(), 2u);
}

TEST(OnnxCheck, ShippedModelAndFixturesPass) {
  for (const std::string& path : {std::string(SEAMAP_SOURCE_DIR) + "/data/models/seabed_objects.onnx",
                                  std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/yolo_v8_fixture.onnx"}) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(bytes.size(), 100u) << path;
    EXPECT_NO_THROW(CheckOnnxGraph(bytes, path)) << path;
  }
}

TEST(OnnxCheck, InitialiserDeclaringMoreThanItHoldsIsRefused) {
  // The issue's model: the largest initializer declares 1e8 elements but holds a few KB.
  OnnxModelSpec spec = TwoBoxModel();
  spec.initializers[0] = testing::FloatTensor("w", {100000000}, std::vector<float>(36, 0.0f));
  const std::string e = CheckError(OnnxModelBytes(spec));
  EXPECT_NE(e.find("hostile.onnx"), std::string::npos) << e;
  EXPECT_NE(e.find("initializer 0 (w)"), std::string::npos) << e;
  EXPECT_NE(e.find("100000000 elements"), std::string::npos) << e;
  EXPECT_NE(e.find("144 bytes"), std::string::npos) << e;
  // One float short, one too many, dims overflowing int64, a negative dim.
  spec.initializers[0] = testing::FloatTensor("w", {6, 3, 1, 1}, std::vector<float>(17, 0.0f));
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("holds 68 bytes"), std::string::npos);
  spec.initializers[0] = testing::FloatTensor("w", {6, 3, 1, 1}, std::vector<float>(19, 0.0f));
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("holds 76 bytes"), std::string::npos);
  spec.initializers[0] = testing::FloatTensor("w", {1ll << 40, 1ll << 40, 1ll << 40}, std::vector<float>(18));
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("over 2^48 elements"), std::string::npos);
  spec.initializers[0] = testing::FloatTensor("w", {-6, -3, 1, 1}, std::vector<float>(18));
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("negative"), std::string::npos);
  // Typed data (float_data, packed) counted the same way; an unknown data type.
  std::string typed;
  testing::PutVarintField(&typed, 1, 6);
  testing::PutVarintField(&typed, 2, 1);
  testing::PutBytesField(&typed, 8, "b");
  testing::PutBytesField(&typed, 4, std::string(5 * 4, '\0'));
  spec = TwoBoxModel();
  spec.initializers[1] = typed;
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("holds 5 values"), std::string::npos);
  spec.initializers[1] = testing::TensorBytes("b", {6}, 99, std::string(24, '\0'));
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("data_type 99"), std::string::npos);
}

TEST(OnnxCheck, UndefinedNodeInputsAndOutputsAreRefused) {
  OnnxModelSpec spec = TwoBoxModel();
  spec.initializers.erase(spec.initializers.begin());  // "w" removed
  std::string e = CheckError(OnnxModelBytes(spec));
  EXPECT_NE(e.find("hostile.onnx"), std::string::npos) << e;
  EXPECT_NE(e.find("node 1"), std::string::npos) << e;
  EXPECT_NE(e.find("input 'w'"), std::string::npos) << e;
  // A node that uses a later node's output; a graph output nothing produces.
  spec = TwoBoxModel();
  std::swap(spec.nodes[0], spec.nodes[1]);
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("input 'pooled'"), std::string::npos);
  spec = TwoBoxModel();
  spec.outputs[0] = testing::FloatValueInfo("nowhere", {1, 6, 2});
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("'nowhere' is produced by no node"), std::string::npos);
  // External data is refused (OpenCV would open a path the model names).
  spec = TwoBoxModel();
  testing::PutVarintField(&spec.initializers[1], 14, 1);
  EXPECT_NE(CheckError(OnnxModelBytes(spec)).find("external file"), std::string::npos);
}

TEST(OnnxCheck, IrregularOrHugeFilesAreRefusedBeforeReading) {
  const std::string e = [] {
    try {
      ReadOnnxInfo("/dev/zero");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  }();
  EXPECT_NE(e.find("/dev/zero"), std::string::npos) << e;
  EXPECT_NE(e.find("not a regular file"), std::string::npos) << e;
  try {
    ReadClassesFile("/dev/zero");
    ADD_FAILURE() << "/dev/zero read as a classes file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--classes"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
  testing::TempDir dir;
  const auto big = testing::WriteFile(dir / "names.txt", std::string(kMaxClassesFileBytes + 1, 'a'));
  EXPECT_THROW(ReadClassesFile(big.string()), InputError);
}

TEST(OnnxCheck, ClassNamesEmptyOrWithHugeIdsAreRefused) {
  const auto error = [](const std::string& text) {
    try {
      ParseClassNames(text, "m.onnx");
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "names") << text;
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("{99999999999999: 'tyre'}").find("too large"), std::string::npos);
  EXPECT_NE(error(R"(["", ""])").find("class 0 has an empty name"), std::string::npos);
  EXPECT_NE(error("{0: 'tyre', 1: '  '}").find("class 1 has an empty name"), std::string::npos);
  // A 10 MB text is quoted, not echoed.
  EXPECT_LT(error("{" + std::string(10 << 20, 'x')).size(), 400u);
}

}  // namespace
}  // namespace seamap
