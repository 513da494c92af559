#include "core/controllers/object_detection.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

ObjectDetectionOptions Valid() {
  ObjectDetectionOptions o;
  o.map_path = "/nonexistent/map.mbtiles";
  o.model_path = "/nonexistent/model.onnx";
  return o;
}

// The option an InputError names (detect names its options as the error's source).
std::string SourceOfError(const ObjectDetectionOptions& o) {
  try {
    o.Check();
  } catch (const InputError& e) {
    return e.file();
  }
  return "";
}

TEST(ObjectDetectionOptionsTest, CheckNamesTheOptionThatDoesNotFit) {
  EXPECT_EQ(SourceOfError(Valid()), "");
  ObjectDetectionOptions o = Valid();
  o.threads = 0;
  EXPECT_EQ(SourceOfError(o), "--threads");
  o.threads = 65;
  EXPECT_EQ(SourceOfError(o), "--threads");
  o = Valid();
  o.layer = "enhanced";
  EXPECT_EQ(SourceOfError(o), "");
  o.layer = "depth";
  EXPECT_EQ(SourceOfError(o), "--layer");
}

TEST(ObjectDetectionTest, ABadLayerIsRefusedBeforeTheModelAndAMissingModelBeforeTheMap) {
  ObjectDetectionOptions o = Valid();
  o.layer = "depth";
  try {
    DetectObjects(o);
    FAIL() << "searched a layer no map has";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "--layer");
  }
  o.layer = "raw";
  try {
    DetectObjects(o);
    FAIL() << "searched without a model";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/model.onnx");
  }
}

}  // namespace
}  // namespace seamap
