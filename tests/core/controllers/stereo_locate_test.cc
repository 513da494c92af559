#include "core/controllers/stereo_locate.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

StereoLocateOptions Valid() {
  StereoLocateOptions o;
  o.calib_path = "/nonexistent/stereo.yaml";
  o.model_path = "/nonexistent/object.json";
  o.pairs_dir = "/nonexistent/pairs";
  o.out = "/nonexistent/pose.json";
  return o;
}

std::string FieldOfError(const StereoLocateOptions& o) {
  try {
    o.Check();
  } catch (const InputError& e) {
    return e.field();
  }
  return "";
}

TEST(StereoLocateOptionsTest, CheckNamesTheOptionThatDoesNotFit) {
  EXPECT_EQ(FieldOfError(Valid()), "");
  StereoLocateOptions o = Valid();
  o.views = 0;
  EXPECT_EQ(FieldOfError(o), "--views");
  o = Valid();
  o.method = "icp";
  EXPECT_EQ(FieldOfError(o), "");
  o.method = "sonar";
  EXPECT_EQ(FieldOfError(o), "--method");
  o = Valid();
  o.time_s = 12;  // when, but on no trajectory
  EXPECT_EQ(FieldOfError(o), "--time");
  o.nav_path = "nav.csv", o.map_path = "map.mbtiles";
  EXPECT_EQ(FieldOfError(o), "");
  o.nav_path.reset();  // the mission's own trajectory
  EXPECT_EQ(FieldOfError(o), "");
  o.pair_times_path = "times.csv";  // --time places the first pair; a table places every pair
  EXPECT_EQ(FieldOfError(o), "--pair-times");
}

// A trajectory without --time is a dive: every pair on its own at its own time.
TEST(StereoLocateOptionsTest, ADiveLocatesPairsOneByOne) {
  StereoLocateOptions o = Valid();
  o.map_path = "map.mbtiles";  // the mission's trajectory
  EXPECT_TRUE(o.Dive());
  EXPECT_EQ(FieldOfError(o), "");
  o.pair_times_path = "times.csv";
  EXPECT_EQ(FieldOfError(o), "");
  o.views = 3;
  EXPECT_EQ(FieldOfError(o), "--views");
  o = Valid();
  o.nav_path = "nav.csv";
  EXPECT_TRUE(o.Dive());
  o.locate.motion.world_from_camera["ap_001"] = Rigid::Identity();
  EXPECT_EQ(FieldOfError(o), "--motion");
  o = Valid();
  EXPECT_FALSE(o.Dive());
  o.pair_times_path = "times.csv";  // no trajectory to read the times on
  EXPECT_EQ(FieldOfError(o), "--pair-times");
}

TEST(StereoLocateTest, RunChecksTheOptionsThenNamesAMissingCalibration) {
  StereoLocateOptions o = Valid();
  o.views = 0;
  try {
    StereoLocate(o).Run();
    FAIL() << "located with no pairs";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--views");
  }
  try {
    StereoLocate(Valid()).Run();
    FAIL() << "located without a calibration";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/stereo.yaml");
  }
}

}  // namespace
}  // namespace seamap
