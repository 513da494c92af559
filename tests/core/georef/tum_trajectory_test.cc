#include "core/georef/tum_trajectory.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

class TumTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) { return WriteFile(dir_ / "keyframes.txt", text).string(); }
  // The InputError the text causes; fails the test when there is none.
  InputError Fatal(const std::string& text) {
    const std::string path = Write(text);
    try {
      ReadTumTrajectory(path);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      return e;
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return InputError("", 0, "", "");
  }
  TempDir dir_;
};

TEST_F(TumTest, ReadsPosesSkippingCommentsAndBlanks) {
  const auto k =
      ReadTumTrajectory(Write("# ORB-SLAM3 keyframes\n\n"
                              "1700000000.123456789 1 2 3 0 0 0 1\r\n"
                              "   # indented comment\n"
                              "1700000001.5 4 5 6 0 0 0.7071068 0.7071068\n"));
  ASSERT_EQ(k.size(), 2u);
  EXPECT_EQ(k[0].line, 3);
  EXPECT_EQ(k[1].line, 5);
  EXPECT_NEAR(k[0].time_s, 1700000000.123456789, 1e-6);  // a double: a float would step by 128 s
  EXPECT_EQ(k[0].position_slam, Eigen::Vector3d(1, 2, 3));
  // Scalar last in the file, 90 degrees about z: x goes to y.
  const Eigen::Vector3d x = k[1].world_from_cam * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(x.y(), 1.0, 1e-6);
  EXPECT_NEAR(k[1].world_from_cam.norm(), 1.0, 1e-15);
}

TEST_F(TumTest, ASevenFieldLineNamesFileAndLine) {
  const InputError e = Fatal("# header\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(std::string(e.what()).find("keyframes.txt:3"), std::string::npos) << e.what();
  EXPECT_NE(e.detail().find("expected 8 numbers"), std::string::npos);
}

TEST_F(TumTest, NineFieldsANonNumberAndABackwardTimestamp) {
  EXPECT_EQ(Fatal("0 0 0 0 0 0 0 1 5\n").line(), 1);
  const InputError word = Fatal("0 0 0 0 0 0 0 1\n1 0 x 0 0 0 0 1\n");
  EXPECT_EQ(word.line(), 2);
  EXPECT_EQ(word.field(), "ty");
  const InputError back = Fatal("5 0 0 0 0 0 0 1\n4 0 0 0 0 0 0 1\n");
  EXPECT_EQ(back.line(), 2);
  EXPECT_EQ(back.field(), "timestamp");
  EXPECT_EQ(Fatal("5 0 0 0 0 0 0 1\n5 0 0 0 0 0 0 1\n").line(), 2);  // repeated
}

TEST_F(TumTest, AQuaternionOffTheUnitSphereIsRefused) {
  const InputError e = Fatal("0 0 0 0 0 0 0 1.5\n");
  EXPECT_EQ(e.field(), "qw");
  EXPECT_NE(e.detail().find("norm"), std::string::npos);
  EXPECT_NO_THROW(ReadTumTrajectory(Write("0 0 0 0 0 0 0 1.005\n")));  // within 1 %: normalised
}

TEST_F(TumTest, EmptyAndMissingFiles) {
  EXPECT_EQ(Fatal("# nothing\n\n").line(), 0);
  EXPECT_THROW(ReadTumTrajectory((dir_ / "absent.txt").string()), InputError);
}

TEST_F(TumTest, WriteReadRoundTrip) {
  std::vector<Keyframe> in(2);
  in[0].time_s = 1700000000.25;
  in[0].position_slam = {1.5, -2.25, 1e-3};
  in[0].world_from_cam = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  in[1].time_s = 1700000001.75;
  in[1].position_slam = {-100, 50, 0.5};
  in[1].world_from_cam = Eigen::Quaterniond::Identity();
  const std::string path = (dir_ / "out.txt").string();
  WriteTumTrajectory(path, in, "test");
  const auto out = ReadTumTrajectory(path);
  ASSERT_EQ(out.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(out[i].time_s, in[i].time_s, 1e-6);
    EXPECT_LT((out[i].position_slam - in[i].position_slam).norm(), 1e-8);
    EXPECT_LT(out[i].world_from_cam.angularDistance(in[i].world_from_cam), 1e-8);
  }
}

}  // namespace
}  // namespace seamap
