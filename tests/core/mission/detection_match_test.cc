#include "core/mission/detection_match.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

constexpr double kDegPerMetre = 1.0 / 111319.49;  // along a meridian

Detection At(double north_m, const std::string& cls, double size_m = 0.6, const std::string& model = "m.onnx#1") {
  Detection d;
  d.class_name = cls;
  d.model = model;
  d.source = "recogniser";
  d.position = {43.1 + north_m * kDegPerMetre, 131.9};
  d.size_m = std::array<double, 2>{size_m, size_m};
  return d;
}

TEST(DetectionMatch, SameObjectNeedsClassModelFileAndDistance) {
  const Detection earlier = At(0, "tyre", 0.8);  // radius max(0.1, 0.8/4) = 0.2 m
  EXPECT_TRUE(SameObject(earlier, At(0.19, "tyre", 0.8)));
  EXPECT_FALSE(SameObject(earlier, At(0.21, "tyre", 0.8)));
  EXPECT_FALSE(SameObject(earlier, At(0.05, "crate", 0.8)));
  EXPECT_TRUE(SameObject(earlier, At(0.05, "tyre", 0.8, "m.onnx#2")));  // another version of the same model
  EXPECT_FALSE(SameObject(earlier, At(0.05, "tyre", 0.8, "other.onnx#1")));
  EXPECT_FALSE(SameObject(earlier, At(0.15, "tyre", 0.2)));  // the smaller object decides: 10 cm
  Detection stereo = At(0, "tyre", 0.8);
  stereo.source = "stereo";
  EXPECT_FALSE(SameObject(earlier, stereo)) << "another kind of finder's object is its own";
  Detection mark = earlier;
  mark.source = "operator";
  EXPECT_FALSE(SameObject(mark, At(0, "tyre", 0.8)));
}

TEST(DetectionMatch, NearestPairsFirstOneToOne) {
  const std::vector<Detection> earlier = {At(0, "tyre", 0.8), At(0.3, "tyre", 0.8), At(5, "rock")};
  // found[0] is 0.12 m from earlier[0] and 0.18 from earlier[1]; found[1] is 0.02 from earlier[0].
  const std::vector<Detection> found = {At(0.12, "tyre", 0.8), At(0.02, "tyre", 0.8), At(9, "rock")};
  const std::vector<int> match = MatchEarlier(earlier, found);
  ASSERT_EQ(match.size(), 3u);
  EXPECT_EQ(match[1], 0);   // the nearest pair goes first
  EXPECT_EQ(match[0], 1);   // so the other one continues the next nearest
  EXPECT_EQ(match[2], -1);  // 4 m away: a new object
  EXPECT_TRUE(MatchEarlier({}, found) == std::vector<int>(3, -1));
}

TEST(DetectionMatch, GroundDistance) {
  EXPECT_NEAR(GroundDistanceM(At(0, "a").position, At(1, "a").position), 1.0, 1e-3);
  EXPECT_EQ(ModelFile("seabed_objects.onnx#abc"), "seabed_objects.onnx");
  EXPECT_EQ(ModelFile("plain.onnx"), "plain.onnx");
}

}  // namespace
}  // namespace seamap
