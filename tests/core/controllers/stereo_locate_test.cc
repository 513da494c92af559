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
  o.map_path = "map.mbtiles";  // where the vehicle was: unknown
  EXPECT_EQ(FieldOfError(o), "--map");
  o = Valid();
  o.nav_path = "nav.csv";
  EXPECT_EQ(FieldOfError(o), "--time");
  o = Valid();
  o.time_s = 12;
  EXPECT_EQ(FieldOfError(o), "--nav");
  o.nav_path = "nav.csv", o.map_path = "map.mbtiles";
  EXPECT_EQ(FieldOfError(o), "");
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
