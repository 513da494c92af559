// `seamap simulate --relief` from the command line: the truth it writes, and
// its errors naming the option or file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/sim/ground_truth.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
namespace fs = std::filesystem;

const char* kSmall =
    " --quiet --frames 12 --width 160 --height 120 --line-spacing 0.3 --altitude-min 2 --altitude-max 2";

TEST(Relief, SimulateWritesTheTrueTerrain) {
  const testing::SimulatedSurvey& s = testing::SharedSurvey("relief", std::string(kSmall) + " --relief 0.2");
  ASSERT_TRUE(fs::exists(s.dir + "/truth/terrain.tif"));
  const GroundTruth truth = GroundTruth::Load(s.dir);
  ASSERT_FALSE(truth.terrain.empty());
  cv::Scalar mean, stddev;
  cv::meanStdDev(truth.terrain.height_m, mean, stddev);
  EXPECT_NEAR(mean[0], -35, 1e-3);
  EXPECT_NEAR(stddev[0], 0.2, 1e-3);
}

TEST(Relief, BadReliefOptionsAreNamed) {
  testing::TempDir dir;
  std::string out;
  const std::string base = "simulate --out " + (dir / "s").string() + kSmall;
  EXPECT_EQ(Seamap(base + " --relief -0.1", &out), 2);
  EXPECT_NE(out.find("--relief"), std::string::npos) << out;
  const std::string missing = (dir / "heights.png").string();
  EXPECT_EQ(Seamap(base + " --relief 0.2 --relief-texture " + missing, &out), 2);
  EXPECT_NE(out.find(missing), std::string::npos) << out;
  EXPECT_NE(out.find("--relief-texture"), std::string::npos) << out;
  EXPECT_EQ(Seamap(base + " --relief-texture " + missing, &out), 2);  // no --relief to scale it to
  EXPECT_NE(out.find("needs --relief"), std::string::npos) << out;
}

}  // namespace
}  // namespace seamap
