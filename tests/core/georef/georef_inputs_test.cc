#include "core/georef/georef_inputs.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

TEST(ReadBuoyLog, AliasesQualityColumnsAndBadRows) {
  TempDir dir;
  const std::string path = WriteFile(dir / "buoy.csv",
                                     "Timestamp;Latitude;Longitude;HDOP;Fix\n"
                                     "100,0;51,05;13,62;1,2;1\n"
                                     "101,0;51,0501;13,62;0,9;0\n"
                                     "102,0;abc;13,62;1,0;1\n"
                                     "103,0;51,0502;13,6201;1,1;2\n")
                               .string();
  const BuoyLog log = ReadBuoyLog(path);
  ASSERT_EQ(log.fixes.size(), 2u);
  EXPECT_EQ(log.fixes[0].line, 2);
  EXPECT_NEAR(log.fixes[0].position.lat, 51.05, 1e-9);
  EXPECT_NEAR(log.fixes[0].position.lon, 13.62, 1e-9);
  EXPECT_DOUBLE_EQ(log.fixes[0].hdop, 1.2);
  EXPECT_NEAR(log.fixes[1].position.lat, 51.0502, 1e-9);
  ASSERT_EQ(log.rejected.size(), 2u);
  EXPECT_EQ(log.rejected[0].line, 3);
  EXPECT_EQ(log.rejected[0].field, "fix_quality");
  EXPECT_EQ(log.rejected[1].line, 4);
  EXPECT_EQ(log.rejected[1].field, "lat");
}

TEST(ReadBuoyLog, NeedsTimesAndFixes) {
  TempDir dir;
  EXPECT_THROW(ReadBuoyLog(WriteFile(dir / "a.csv", "image,lat,lon\na.jpg,51,13\nb.jpg,51,13\n").string()), InputError);
  try {
    ReadBuoyLog(WriteFile(dir / "b.csv", "time_s,lat,lon\n1,x,13\n2,y,13\n").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
  }
}

TEST(ReadDepthLog, ReadsAndRejectsByLine) {
  TempDir dir;
  const DepthLog log =
      ReadDepthLog(WriteFile(dir / "depth.csv", "time,depth\n1,12.5\n2,-1\n3,12.7\n4,deep\n").string());
  ASSERT_EQ(log.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(log.samples[1].second, 12.7);
  ASSERT_EQ(log.rejected.size(), 2u);
  EXPECT_EQ(log.rejected[0].line, 3);
  EXPECT_EQ(log.rejected[1].field, "depth_m");
  try {
    ReadDepthLog(WriteFile(dir / "nodepth.csv", "time_s,alt\n1,2\n").string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "depth_m");
    EXPECT_EQ(e.line(), 1);
  }
}

}  // namespace
}  // namespace seamap
