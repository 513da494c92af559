// Randomised ONNX models (tests/testing/fuzz.h, issue 33): seeded mutations
// of a small valid hand-built model, on the wire (bytes replaced, inserted,
// removed) and in its structure (dims, shapes, initializers, node inputs),
// either load into a model that runs, or stop with an InputError naming the
// file. Never a crash (OpenCV is only given models the check passed) or
// another kind of exception.
#include <gtest/gtest.h>

#include "core/detect/onnx_meta.h"
#include "core/detect/yolo_model.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/onnx_builder.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::OnnxModelSpec;

OnnxModelSpec SmallModel() {
  return testing::PlantedYoloModel({1, 6, 2},
                                   testing::V8Values({{20, 24, 10, 8, 0.1f, 0.8f}, {44, 40, 12, 12, 0.9f, 0.2f}}),
                                   {{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", "0.5"}});
}

// The model with one structural change a careless export or an attacker could make.
OnnxModelSpec MutateStructure(Fuzz& fuzz, OnnxModelSpec spec) {
  const auto dims = [&]() {
    std::vector<int64_t> d;
    for (size_t i = fuzz.Below(5); i > 0; --i)
      d.push_back(fuzz.Pick(std::vector<int64_t>{0, 1, 2, 3, 6, 18, -1, 100000000, int64_t{1} << 62}));
    return d;
  };
  switch (fuzz.Below(7)) {
    case 0:  // an initializer with other dims, data unchanged
      spec.initializers[fuzz.Below(3)] = testing::FloatTensor("w", dims(), std::vector<float>(18, 0.0f));
      break;
    case 1:  // an initializer removed
      spec.initializers.erase(spec.initializers.begin() + static_cast<std::ptrdiff_t>(fuzz.Below(3)));
      break;
    case 2: {  // other dims with data that fits them (OpenCV must still not crash)
      const std::vector<int64_t> d = dims();
      int64_t n = 1;
      for (int64_t x : d) n = x < 0 || x > 64 ? -1 : (n < 0 ? -1 : n * x);
      if (n >= 0)
        spec.initializers[fuzz.Below(2)] =
            testing::FloatTensor(fuzz.OneIn(2) ? "w" : "b", d, std::vector<float>(n, 1.0f));
      break;
    }
    case 3:  // the reshape's target
      spec.initializers[2] = testing::TensorBytes("shape", {3}, 7, testing::RawOf(dims()));
      break;
    case 4:  // a node input renamed
      spec.nodes[fuzz.Below(3)].inputs[0] = fuzz.Pick(std::vector<std::string>{"", "images", "nowhere", "planted"});
      break;
    case 5:  // the graph input's or output's dims
      (fuzz.OneIn(2) ? spec.inputs[0] : spec.outputs[0]) =
          testing::FloatValueInfo(fuzz.OneIn(2) ? "images" : "output0", dims());
      break;
    default:  // the convolution's kernel attribute
      spec.nodes[1].attributes = {testing::IntsAttribute("kernel_shape", dims())};
      break;
  }
  return spec;
}

void Check(Fuzz& fuzz, const std::string& path, const std::string& bytes) {
  SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ", " + std::to_string(bytes.size()) + " bytes");
  testing::WriteFile(path, bytes);
  try {
    const auto info = YoloModel::Inspect(path, "");
    YoloModel model(info);
    model.Detect(cv::Mat(40, 50, CV_8UC3, cv::Scalar::all(100)), info->min_score);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path) << e.what();
    EXPECT_LT(std::string(e.what()).size(), 2000u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
}

TEST(OnnxFuzz, MutatedBytesLoadAWorkingModelOrAreRefusedByName) {
  testing::TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "fuzzed.onnx").string();
  const std::string valid = testing::OnnxModelBytes(SmallModel());
  while (fuzz.More()) Check(fuzz, path, fuzz.Mutate(valid));
}

TEST(OnnxFuzz, MutatedStructureLoadsAWorkingModelOrIsRefusedByName) {
  testing::TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "fuzzed.onnx").string();
  while (fuzz.More()) Check(fuzz, path, testing::OnnxModelBytes(MutateStructure(fuzz, SmallModel())));
}

// The metadata a search reads (names, imgsz, seamap.*) with hostile values.
TEST(OnnxFuzz, HostileMetadataLoadsOrIsRefusedByName) {
  testing::TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "fuzzed.onnx").string();
  const std::vector<std::string> names = {R"(["tyre", "crate"])", "{0: 'tyre', 1: 'crate'}", "{1: 'crate', 0: 'tyre'}"};
  const std::vector<std::string> keys = {"names", "imgsz", "seamap.min_score", "seamap.class_sizes_m", "seamap.layer"};
  while (fuzz.More()) {
    OnnxModelSpec spec = SmallModel();
    const std::string key = fuzz.Pick(keys);
    const std::string base = key == "names"                  ? fuzz.Pick(names)
                             : key == "imgsz"                ? "[64, 64]"
                             : key == "seamap.class_sizes_m" ? R"({"tyre": [0.5, 1.0], "crate": 1.2})"
                                                             : "0.5";
    std::string value = fuzz.Mutate(base);
    if (fuzz.OneIn(3)) {  // a number replaced by a hostile one
      const size_t at = value.find_first_of("0123456789");
      if (at != std::string::npos) value.replace(at, 1, fuzz.HostileNumber());
    }
    if (fuzz.OneIn(20)) value = std::string(1 << 20, value.empty() ? '7' : value[0]);
    spec.metadata[key] = value;
    Check(fuzz, path, testing::OnnxModelBytes(spec));
  }
}

}  // namespace
}  // namespace seamap
