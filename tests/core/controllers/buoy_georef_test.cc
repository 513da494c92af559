#include "core/controllers/buoy_georef.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

BuoyGeorefOptions Valid() {
  BuoyGeorefOptions o;
  o.keyframe_files = {"keyframes.txt"};
  o.buoy_file = "buoy.csv";
  o.tether_length_m = 30;
  o.depth_m = 10;
  o.out = "nav.csv";
  return o;
}

std::string FieldOfError(const BuoyGeorefOptions& o) {
  try {
    o.Check();
  } catch (const InputError& e) {
    return e.field();
  }
  return "";
}

TEST(BuoyGeorefOptionsTest, CheckNamesTheOptionThatDoesNotFit) {
  EXPECT_EQ(FieldOfError(Valid()), "");
  BuoyGeorefOptions o = Valid();
  o.keyframe_files.clear();
  EXPECT_EQ(FieldOfError(o), "--keyframes");
  o = Valid();
  o.tether_length_m = -1;
  EXPECT_EQ(FieldOfError(o), "--tether-length");
  o = Valid();
  o.depth_m = 30;  // the tether's length: the buoy would be straight above
  EXPECT_EQ(FieldOfError(o), "--depth");
  o = Valid();
  o.depth_file = "depth.csv";  // and --depth: one of the two
  EXPECT_EQ(FieldOfError(o), "--depth");
  o = Valid();
  o.points_out = "out.ply";
  EXPECT_EQ(FieldOfError(o), "--points");
  o = Valid();
  o.altitude_from_cloud = true;
  EXPECT_EQ(FieldOfError(o), "--altitude-from-cloud");
  o.points = "in.ply", o.points_out = "out.ply", o.altitude_file = "altitude.csv";
  EXPECT_EQ(FieldOfError(o), "--altitude-from-cloud");
}

TEST(BuoyGeorefTest, AMissingKeyframeFileIsNamed) {
  BuoyGeorefOptions o = Valid();
  o.keyframe_files = {"/nonexistent/keyframes.txt"};
  try {
    BuoyGeoref(o).Run();
    FAIL() << "ran without keyframes";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/keyframes.txt");
  }
}

}  // namespace
}  // namespace seamap
