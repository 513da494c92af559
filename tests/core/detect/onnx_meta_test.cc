#include "core/detect/onnx_meta.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

const std::string kFixtures = std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/";

TEST(OnnxMeta, ReadsInputDimsAndMetadataOfTheFixtures) {
  const OnnxInfo v5 = ReadOnnxInfo(kFixtures + "yolo_v5_fixture.onnx");
  EXPECT_EQ(v5.ir_version, 7);
  EXPECT_EQ(v5.input_dims, (std::vector<int64_t>{1, 3, 64, 64}));  // initialisers are not inputs
  EXPECT_EQ(v5.outputs, 1);
  EXPECT_EQ(v5.metadata.at("names"), "{0: 'tyre', 1: 'crate'}");
  const OnnxInfo v8 = ReadOnnxInfo(kFixtures + "yolo_v8_fixture.onnx");
  EXPECT_EQ(ParseClassNames(v8.metadata.at("names"), "m"), (std::vector<std::string>{"tyre", "crate"}));
  EXPECT_EQ(ParseClassSizes(v8.metadata.at("seamap.class_sizes_m"), {"tyre", "crate"}, "m"),
            (std::vector<double>{1.0, 1.2}));
  EXPECT_EQ(v8.metadata.at("seamap.layer"), "raw");
  // A [smallest, largest] range per class (the shipped model's form): the largest counts.
  EXPECT_EQ(ParseClassSizes(R"({"tyre": [0.5, 1.0], "crate": [0.4, 1.2]})", {"tyre", "crate"}, "m"),
            (std::vector<double>{1.0, 1.2}));
  EXPECT_THROW(ParseClassSizes(R"({"tyre": [0.5, 1.0, 2.0]})", {"tyre"}, "m"), InputError);
}

TEST(OnnxMeta, TextFileIsNotAnOnnxModel) {
  testing::TempDir dir;
  const auto path = testing::WriteFile(dir / "model.onnx", "this is a text file\nnot a model\n");
  try {
    ReadOnnxInfo(path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.onnx"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not an ONNX model"), std::string::npos) << e.what();
  }
  // A valid protobuf that is not a ModelProto (only field 1).
  EXPECT_THROW(ParseOnnxInfo(std::string("\x08\x07", 2), "x.onnx"), InputError);
  EXPECT_THROW(ParseOnnxInfo("", "x.onnx"), InputError);
}

TEST(OnnxMeta, TruncatedModelIsRejected) {
  testing::TempDir dir;
  std::string bytes;
  {
    std::ifstream in(kFixtures + "yolo_v8_fixture.onnx", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_THROW(ParseOnnxInfo(bytes.substr(0, bytes.size() / 2), "half.onnx"), InputError);
}

TEST(OnnxMeta, ClassNamesAsJsonListOrPythonDict) {
  EXPECT_EQ(ParseClassNames(R"(["a", "b c"])", "s"), (std::vector<std::string>{"a", "b c"}));
  EXPECT_EQ(ParseClassNames("{0: 'tyre', 1: \"crate\", 2: 'pipe'}", "s"),
            (std::vector<std::string>{"tyre", "crate", "pipe"}));
  EXPECT_EQ(ParseClassNames("{1: 'b', 0: 'a'}", "s"), (std::vector<std::string>{"a", "b"}));
  EXPECT_THROW(ParseClassNames("{0: 'a', 2: 'c'}", "s"), InputError);  // gap
  EXPECT_THROW(ParseClassNames("tyre,crate", "s"), InputError);
  EXPECT_THROW(ParseClassNames("[]", "s"), InputError);
  EXPECT_THROW(ParseClassNames("[1, 2]", "s"), InputError);
  EXPECT_THROW(ParseClassSizes("{\"tyre\": -1}", {"tyre"}, "s"), InputError);
  EXPECT_EQ(ParseClassSizes("[0.5, 2]", {"a", "b", "c"}, "s"), (std::vector<double>{0.5, 2, 0}));
}

TEST(OnnxMeta, ClassesFileSkipsCommentsAndBlankLines) {
  testing::TempDir dir;
  const auto path = testing::WriteFile(dir / "names.txt", "# classes\ntyre\n\n crate  # wooden\n");
  EXPECT_EQ(ReadClassesFile(path.string()), (std::vector<std::string>{"tyre", "crate"}));
  const auto empty = testing::WriteFile(dir / "empty.txt", "# nothing\n");
  EXPECT_THROW(ReadClassesFile(empty.string()), InputError);
  EXPECT_THROW(ReadClassesFile((dir / "missing.txt").string()), InputError);
}

}  // namespace
}  // namespace seamap
